#include "fleetnav/sim/exteroceptive_sensors.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

namespace fleetnav::sim {
namespace {

bool Dropped(const std::set<std::string>& dropped, const std::string& name) {
  return dropped.count(name) != 0 || dropped.count("") != 0;
}

}  // namespace

SensingScene StaticScene(const WorldDescription& world) {
  SensingScene scene;
  for (const BoxObstacle& box : world.boxes) {
    scene.statics.push_back(BoxShape(box.center_m, box.size_m, box.yaw_rad, box.height_m, -1));
  }
  for (const CylinderObstacle& cylinder : world.cylinders) {
    scene.statics.push_back(
        CircleShape(cylinder.center_m, cylinder.radius_m, cylinder.height_m, -1));
    if (cylinder.kind == "charging_pole") scene.charging_poles.push_back(scene.statics.back());
  }
  for (const FloorStripe& stripe : world.stripes) {
    for (size_t i = 0; i + 1 < stripe.points_m.size(); ++i) {
      scene.strips.push_back(
          {stripe.points_m[i], stripe.points_m[i + 1], 0.5 * stripe.width_m, true});
    }
  }
  for (const StripeMarker& marker : world.markers) {
    const Eigen::Vector2d half =
        0.5 * marker.length_m * Eigen::Vector2d(std::cos(marker.yaw_rad), std::sin(marker.yaw_rad));
    scene.strips.push_back({marker.position_m - half, marker.position_m + half, 0.025, false});
  }
  return scene;
}

ExteroceptiveSensors::ExteroceptiveSensors(const RobotModel& model, ExteroceptiveParams params,
                                           uint64_t simulation_seed, const std::string& robot_id)
    : model_(model), params_(params) {
  for (const SensorMount& mount : model.sensors) {
    streams_.emplace(mount.name, NoiseStream(NoiseSeed(simulation_seed, robot_id, mount.name)));
  }
}

NoiseStream& ExteroceptiveSensors::Stream(const std::string& sensor) { return streams_.at(sensor); }

bool ExteroceptiveSensors::EveryTicks(uint64_t tick, double rate_hz, double period_s) const {
  const auto every = static_cast<uint64_t>(std::max(1.0, std::round(1.0 / (rate_hz * period_s))));
  return tick % every == 0;
}

std::vector<const Shape2*> ExteroceptiveSensors::Candidates(const SensingScene& scene,
                                                            int robot_index,
                                                            const Eigen::Vector2d& origin,
                                                            double reach_m, double z_m) const {
  std::vector<const Shape2*> out;
  auto consider = [&](const Shape2& shape) {
    if (shape.owner == robot_index && robot_index >= 0) return;
    if (shape.height_m < z_m) return;  // the beam passes over it
    if ((shape.center - origin).norm() > reach_m + shape.radius) return;
    out.push_back(&shape);
  };
  for (const Shape2& shape : scene.statics) consider(shape);
  for (const Shape2& shape : scene.robots) consider(shape);
  return out;
}

ExteroceptiveSensors::Hit ExteroceptiveSensors::Cast(const SensingScene&,
                                                     const std::vector<const Shape2*>& candidates,
                                                     const Eigen::Vector2d& origin,
                                                     const Eigen::Vector2d& direction,
                                                     double max_m) const {
  Hit best{max_m, Eigen::Vector2d::UnitX(), false};
  for (const Shape2* shape : candidates) {
    std::optional<RayHit> hit = CastRay(*shape, origin, direction, best.distance_m);
    if (hit && hit->distance_m <= best.distance_m) best = {hit->distance_m, hit->normal, true};
  }
  return best;
}

void ExteroceptiveSensors::Sample(const SensingScene& scene, int robot_index, const Pose2& pose,
                                  uint64_t tick, double period_s,
                                  const std::set<std::string>& dropped, SensorFrame* frame) {
  for (const SensorMount& mount : model_.sensors) {
    const Pose2 sensor_pose = pose * mount.pose_in_base;
    const Eigen::Vector2d origin = sensor_pose.translation();
    const bool off = Dropped(dropped, mount.name);
    switch (mount.type) {
      case SensorType::kUltrasonic: {
        const UltrasonicParams& p = params_.ultrasonic;
        NoiseStream& noise = Stream(mount.name);
        const double noise_draw = noise.Gaussian(p.noise_stddev_m);
        const bool lost = noise.Uniform() < p.dropout_probability;
        const std::vector<const Shape2*> candidates =
            Candidates(scene, robot_index, origin, p.max_range_m, mount.z_m);
        double nearest = p.max_range_m;
        bool echo = false;
        for (int i = 0; i < p.rays; ++i) {
          const double offset =
              p.rays > 1 ? -0.5 * p.cone_rad + p.cone_rad * i / (p.rays - 1) : 0.0;
          const double angle = sensor_pose.yaw_rad() + offset;
          const Eigen::Vector2d direction(std::cos(angle), std::sin(angle));
          const Hit hit = Cast(scene, candidates, origin, direction, p.max_range_m);
          if (!hit.found) continue;
          const Eigen::Vector2d point = origin + hit.distance_m * direction;
          bool hidden = false;
          for (const FaultSpec& region : scene.ultrasonic_hidden) hidden |= region.InRegion(point);
          if (hidden) continue;
          if (std::acos(std::clamp(-direction.dot(hit.normal), -1.0, 1.0)) > p.max_incidence_rad) {
            continue;
          }
          echo = true;
          nearest = std::min(nearest, hit.distance_m);
        }
        RangeReading reading{mount.name, p.max_range_m, false};
        if (echo && !lost && !off) {
          reading.echo = true;
          reading.range_m = std::clamp(nearest + noise_draw, p.min_range_m, p.max_range_m);
        }
        frame->ultrasonic.push_back(reading);
        break;
      }
      case SensorType::kInductive: {
        bool detected = false;
        for (const SensingScene::Strip& strip : scene.strips) {
          if (OnSegmentStrip(strip.a, strip.b, strip.half_width_m, origin)) {
            detected = true;
            break;
          }
        }
        // The lateral line through the sensor: where does a follow stripe cross it?
        const Eigen::Vector2d lateral(-std::sin(sensor_pose.yaw_rad()),
                                      std::cos(sensor_pose.yaw_rad()));
        std::optional<double> offset;
        for (const SensingScene::Strip& strip : scene.strips) {
          if (!strip.follow) continue;
          const Eigen::Vector2d d = strip.b - strip.a;
          const double length = d.norm();
          if (length <= 0.0) continue;
          const Eigen::Vector2d u = d / length;
          const double cross = lateral.x() * u.y() - lateral.y() * u.x();  // sin of the angle
          if (std::abs(cross) < std::sin(params_.inductive_min_crossing_rad)) continue;
          // origin + t·lateral = a + s·u
          const Eigen::Vector2d w = strip.a - origin;
          const double t = (w.x() * u.y() - w.y() * u.x()) / cross;
          const double along = (w.x() * lateral.y() - w.y() * lateral.x()) / cross;
          if (std::abs(t) > params_.inductive_range_m || along < 0.0 || along > length) continue;
          if (!offset || std::abs(t) < std::abs(*offset)) offset = t;
        }
        if (offset && !off) {
          offset = *offset + Stream(mount.name).Gaussian(params_.inductive_noise_m);
        } else {
          offset.reset();
        }
        frame->inductive.push_back({mount.name, detected && !off, offset});
        break;
      }
      case SensorType::kLaser: {
        const LaserParams& p = model_.kinematics == Kinematics::kAckermann ? params_.ackermann_laser
                                                                           : params_.omni_laser;
        if (!EveryTicks(tick, p.rate_hz, period_s)) break;
        NoiseStream& noise = Stream(mount.name);
        LaserScanSample scan;
        scan.name = mount.name;
        scan.range_max_m = p.max_range_m;
        scan.angle_min_rad = -0.5 * p.fov_rad;
        scan.angle_increment_rad = p.beams > 1 ? p.fov_rad / (p.beams - 1) : 0.0;
        scan.ranges_m.resize(static_cast<size_t>(p.beams));
        const std::vector<const Shape2*> candidates =
            Candidates(scene, robot_index, origin, p.max_range_m, mount.z_m);
        for (int i = 0; i < p.beams; ++i) {
          const double angle =
              sensor_pose.yaw_rad() + scan.angle_min_rad + i * scan.angle_increment_rad;
          const Eigen::Vector2d direction(std::cos(angle), std::sin(angle));
          const Hit hit = Cast(scene, candidates, origin, direction, p.max_range_m);
          const double n = noise.Gaussian(p.noise_stddev_m);
          double range = p.max_range_m;
          if (hit.found && !off)
            range = std::clamp(hit.distance_m + n, p.min_range_m, p.max_range_m);
          scan.ranges_m[static_cast<size_t>(i)] = static_cast<float>(range);
        }
        frame->lasers.push_back(std::move(scan));
        break;
      }
      case SensorType::kChargerContact: {
        bool contact = false;
        for (const Shape2& pole : scene.charging_poles) {
          contact |= (pole.center - origin).norm() <= pole.radius + params_.charger_reach_m;
        }
        frame->charger_contact = contact && !off;
        break;
      }
      case SensorType::kBumper: {
        const Shape2 grown = FootprintShape(model_.footprint_m, pose, model_.height_m, robot_index,
                                            params_.bumper_margin_m);
        bool touching = false;
        for (const Shape2& shape : scene.statics) {
          if (Overlap(grown, shape)) {
            touching = true;
            break;
          }
        }
        for (const Shape2& shape : scene.robots) {
          if (touching) break;
          if (shape.owner != robot_index && Overlap(grown, shape)) touching = true;
        }
        frame->bumper = touching && !off;
        break;
      }
      case SensorType::kGps: {
        if (!EveryTicks(tick, params_.gps.rate_hz, period_s)) break;
        NoiseStream& noise = Stream(mount.name);
        const double nx = noise.Gaussian(params_.gps.stddev_m);
        const double ny = noise.Gaussian(params_.gps.stddev_m);
        if (!off) frame->gps = GpsFix{origin.x() + nx, origin.y() + ny, params_.gps.stddev_m};
        break;
      }
      case SensorType::kWheelEncoder:
      case SensorType::kImu:
        break;  // proprioceptive_sensors.hpp
    }
  }
}

}  // namespace fleetnav::sim
