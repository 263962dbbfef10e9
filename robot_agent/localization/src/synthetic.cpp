#include "fleetnav/localization/synthetic.hpp"

#include <cmath>

#include "fleetnav/core/angles.hpp"

namespace fleetnav::localization {
namespace {

void FillRect(std::vector<int8_t>& cells, int w, int h, double res, double x0, double y0, double x1,
              double y1) {
  const double origin = -13.0;
  for (int y = 0; y < h; ++y) {
    const double cy = origin + (y + 0.5) * res;
    if (cy < y0 || cy > y1) continue;
    for (int x = 0; x < w; ++x) {
      const double cx = origin + (x + 0.5) * res;
      if (cx >= x0 && cx <= x1) cells[static_cast<size_t>(y) * w + x] = 100;
    }
  }
}

void FillDisc(std::vector<int8_t>& cells, int w, int h, double res, double cx, double cy,
              double r) {
  const double origin = -13.0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const double px = origin + (x + 0.5) * res;
      const double py = origin + (y + 0.5) * res;
      if (std::hypot(px - cx, py - cy) <= r) cells[static_cast<size_t>(y) * w + x] = 100;
    }
  }
}

}  // namespace

absl::StatusOr<OccupancyGrid> SyntheticBarnMap(double resolution_m) {
  if (!(resolution_m > 0.0 && resolution_m <= 1.0)) {
    return absl::InvalidArgumentError("resolution_m must be in (0, 1]");
  }
  const int n = static_cast<int>(std::lround(26.0 / resolution_m));
  std::vector<int8_t> cells(static_cast<size_t>(n) * n, 0);
  const double r = resolution_m;
  // Outer walls (0.2 m thick).
  FillRect(cells, n, n, r, -13.0, -13.0, 13.0, -12.8);
  FillRect(cells, n, n, r, -13.0, 12.8, 13.0, 13.0);
  FillRect(cells, n, n, r, -13.0, -13.0, -12.8, 13.0);
  FillRect(cells, n, n, r, 12.8, -13.0, 13.0, 13.0);
  // Feeding fences: one cell thick with the alley-side face at y = ±5.85 (a fence two cells
  // thick would give the likelihood field a plateau as wide as the fence).
  FillRect(cells, n, n, r, -10.0, 5.9 - 0.6 * r, 10.0, 5.9 - 0.1 * r);
  FillRect(cells, n, n, r, -10.0, -5.9 + 0.1 * r, 10.0, -5.9 + 0.6 * r);
  // Feed kitchen and charging pole.
  FillRect(cells, n, n, r, 9.5, -3.0, 12.5, 3.0);
  FillDisc(cells, n, n, r, -11.5, 0.0, 0.15);
  // Asymmetric furniture away from the north feed alley: posts, a cubicle row, a water trough.
  FillDisc(cells, n, n, r, -3.0, 0.0, 0.2);
  FillDisc(cells, n, n, r, 6.0, -2.0, 0.2);
  FillDisc(cells, n, n, r, -7.0, -2.5, 0.25);
  FillRect(cells, n, n, r, -8.0, -10.0, -5.0, -8.8);
  FillRect(cells, n, n, r, 2.0, 8.5, 3.0, 11.5);
  FillRect(cells, n, n, r, -11.0, 8.0, -9.5, 8.6);
  FillRect(cells, n, n, r, 4.0, -10.5, 4.6, -8.0);
  return OccupancyGrid::Create(n, n, r, Pose2(-13.0, -13.0, 0.0), std::move(cells));
}

MarkerSet Experiment2Markers() {
  MarkerSet set;
  set.map_id = "barn";
  StripeMarker a;
  a.id = 1;
  a.position_m = {0.0, 4.7};
  a.yaw_rad = NormalizeMarkerYaw(kPi / 2.0);
  a.length_m = 0.6;
  StripeMarker b = a;
  b.id = 2;
  b.position_m = {5.0, 4.7};
  set.markers = {a, b};
  return set;
}

RangeObservation SimulateLaser(const OccupancyGrid& map, const Pose2& pose_in_map, int beams,
                               double range_max_m, double noise_stddev_m, Rng& rng) {
  RangeObservation observation;
  observation.beams.reserve(beams);
  for (int i = 0; i < beams; ++i) {
    const double angle = -kPi + 2.0 * kPi * i / beams;
    const double truth =
        CastRay(map, pose_in_map.translation(), pose_in_map.yaw_rad() + angle, range_max_m);
    RangeBeam beam;
    beam.angle_in_base_rad = angle;
    beam.range_max_m = range_max_m;
    beam.no_echo = truth >= range_max_m;
    beam.range_m = beam.no_echo
                       ? range_max_m
                       : std::clamp(truth + noise_stddev_m * rng.Normal(), 0.0, range_max_m);
    observation.beams.push_back(beam);
  }
  return observation;
}

std::vector<RangeReading> SimulateUltrasonics(const OccupancyGrid& map, const Pose2& pose_in_map,
                                              const RobotModel& model, double range_max_m,
                                              double noise_stddev_m, Rng& rng) {
  std::vector<RangeReading> readings;
  for (const SensorMount& mount : model.sensors) {
    if (mount.type != SensorType::kUltrasonic) continue;
    const Pose2 sensor = pose_in_map * mount.pose_in_base;
    const double truth = CastRay(map, sensor.translation(), sensor.yaw_rad(), range_max_m);
    RangeReading reading;
    reading.name = mount.name;
    reading.echo = truth < range_max_m;
    reading.range_m = reading.echo ? truth + noise_stddev_m * rng.Normal() : range_max_m;
    readings.push_back(reading);
  }
  return readings;
}

absl::StatusOr<Experiment2Result> RunExperiment2(const Experiment2Params& params, uint64_t seed) {
  absl::StatusOr<OccupancyGrid> map = SyntheticBarnMap(0.05);
  if (!map.ok()) return map.status();
  const RobotModel model = LelyVectorModel();
  Rng rng(seed * 7919 + 17);
  AmclParams amcl_params;
  amcl_params.min_particles = amcl_params.max_particles = params.particles;
  amcl_params.seed = seed;
  amcl_params.motion.alpha1 = 0.02;
  amcl_params.motion.alpha2 = 0.0001;
  amcl_params.motion.alpha3 = 0.0004;
  amcl_params.motion.alpha4 = 0.001;
  amcl_params.likelihood_field.sigma_hit_m = 0.05;
  amcl_params.update_min_distance_m = 0.1;
  absl::StatusOr<Amcl> amcl = Amcl::Create(amcl_params, *map);
  if (!amcl.ok()) return amcl.status();
  SamclParams samcl_params;
  samcl_params.mode = params.samcl_mode;
  samcl_params.marker_half_width_m = 0.5 * params.marker_width_m;
  absl::StatusOr<Samcl> samcl =
      Samcl::Create(*std::move(amcl), Experiment2Markers(), model, samcl_params);
  if (!samcl.ok()) return samcl.status();

  const double magnitude =
      params.scale_error_min + (params.scale_error_max - params.scale_error_min) * rng.Uniform();
  const double scale = 1.0 + (rng.Uniform() < 0.5 ? -magnitude : magnitude);
  Pose2 truth(-5.5, 4.7, 0.0);
  Pose2 odom;
  const Pose2 inductive = model.FindSensor("inductive_left")->pose_in_base;
  if (absl::Status s = samcl->amcl().InitializePose(truth, {0.02, 0.02, 0.005}, odom, 0); !s.ok()) {
    return s;
  }
  samcl->RecordOdometry(odom, 0);
  Experiment2Result result;
  const std::vector<double> marker_x = {0.0, 5.0};
  int64_t stamp = 0;
  const int64_t tick_ns = static_cast<int64_t>(params.tick_s * 1e9);
  bool mid_done = false;
  bool over_marker = false;  // the inductive sensor's last sample
  while (truth.x_m() < params.end_x_m) {
    const double step = params.speed_mps * params.tick_s;
    truth = truth * Pose2(step, 0.0, 0.0);
    odom = odom * Pose2(step * scale, 0.0, params.yaw_noise_per_tick_rad * rng.Normal());
    stamp += tick_ns;
    const std::vector<RangeReading> readings = SimulateUltrasonics(
        *map, truth, model, params.ultrasonic_range_max_m, params.ultrasonic_noise_m, rng);
    absl::StatusOr<RangeObservation> observation =
        FakeLaserFromUltrasonics(readings, model, params.ultrasonic_range_max_m);
    if (!observation.ok()) return observation.status();
    if (absl::StatusOr<bool> u = samcl->Update(odom, *observation, stamp); !u.ok()) {
      return u.status();
    }
    // The inductive sensor, sampled once a tick: metal while its point is over a strip. A
    // rising edge is the first sample over one, stamped with the tick (as the simulator's
    // sensor is); the check after it counts only when the filter applied a calibration.
    const double s1 = (truth * inductive).x_m();
    bool over = false;
    for (double mx : marker_x) over = over || std::abs(s1 - mx) <= 0.5 * params.marker_width_m;
    const bool rising = over && !over_marker;
    over_marker = over;
    if (rising) {
      const double before = std::abs(samcl->amcl().PoseInMap(odom).x_m() - truth.x_m());
      result.along_track_before_marker_m.push_back(before);
      bool applied = !params.use_samcl;
      if (params.use_samcl) {
        absl::StatusOr<CalibrationResult> c =
            samcl->OnInductiveEdge(InductiveEdge{"inductive_left", stamp});
        if (!c.ok()) return c.status();
        applied = c->outcome == CalibrationOutcome::kApplied;
        if (applied) ++result.calibrations;
      }
      if (applied) {
        result.along_track_after_marker_m.push_back(
            std::abs(samcl->amcl().PoseInMap(odom).x_m() - truth.x_m()));
      }
    }
    const Pose2 estimate = samcl->amcl().PoseInMap(odom);
    result.lateral_max_m = std::max(result.lateral_max_m, std::abs(estimate.y_m() - truth.y_m()));
    if (!mid_done && truth.x_m() >= 0.5) {
      result.along_track_mid_m = std::abs(estimate.x_m() - truth.x_m());
      mid_done = true;
    }
    result.along_track_final_m = std::abs(estimate.x_m() - truth.x_m());
  }
  return result;
}

}  // namespace fleetnav::localization
