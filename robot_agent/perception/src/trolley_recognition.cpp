#include "fleetnav/robot_agent/trolley_recognition.hpp"

#include <algorithm>
#include <cmath>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/robot_agent/scan_features.hpp"

namespace fleetnav::agent {

absl::Status TrolleySpec::Validate() const {
  for (double v : {leg_spacing_x_m, leg_spacing_y_m, leg_radius_m, spacing_tolerance_m,
                   cluster_gap_m, max_leg_extent_m}) {
    if (!(v > 0.0) || !std::isfinite(v)) {
      return absl::InvalidArgumentError("trolley spec: lengths must be finite and > 0");
    }
  }
  return shadow.Validate();
}

namespace {

/// Leg-sized clusters of a scan fitted with a circle of the leg radius, in base_link; with
/// `walls_out`, clusters the iterative end-point fit finds straight (a short piece of wall: a
/// leg's arc is one segment no longer than it) are left out.
std::vector<Eigen::Vector2d> LegCircles(const LaserScanSample& scan, const Pose2& laser_in_base,
                                        const TrolleySpec& spec, bool walls_out) {
  const LaserScanSample clean = RemoveShadows(scan, spec.shadow);
  std::vector<Eigen::Vector2d> legs;
  for (const std::vector<Eigen::Vector2d>& cluster :
       ClusterPoints(ScanPoints(clean, laser_in_base), spec.cluster_gap_m)) {
    if ((cluster.back() - cluster.front()).norm() > spec.max_leg_extent_m) continue;
    if (walls_out && IterativeEndPointFit(cluster, 0.01, 5.0 * kPi / 180.0).size() > 2) continue;
    const std::optional<Circle> circle =
        FitCircleOfRadius(cluster, spec.leg_radius_m, laser_in_base.translation());
    if (circle) legs.push_back(circle->center_m);
  }
  return legs;
}

/// How far from a robot standing under a trolley its legs can be: the half-diagonal, and 15 cm
/// for a trolley standing off the robot's centre.
double LegReachM(const TrolleySpec& spec) {
  return 0.5 * std::hypot(spec.leg_spacing_x_m, spec.leg_spacing_y_m) + 0.15;
}

}  // namespace

std::vector<Eigen::Vector2d> LegCandidates(const LaserScanSample& scan, const Pose2& laser_in_base,
                                           const TrolleySpec& spec) {
  return LegCircles(scan, laser_in_base, spec, /*walls_out=*/true);
}

std::vector<Eigen::Vector2d> LegsAround(const LaserScanSample& scan, const Pose2& laser_in_base,
                                        const TrolleySpec& spec) {
  std::vector<Eigen::Vector2d> legs = LegCircles(scan, laser_in_base, spec, /*walls_out=*/false);
  std::erase_if(legs, [&](const Eigen::Vector2d& leg) { return leg.norm() > LegReachM(spec); });
  return legs;
}

std::vector<TrolleyDetection> RecognizeTrolleys(const std::vector<Eigen::Vector2d>& legs,
                                                const TrolleySpec& spec) {
  const auto matches = [&](double d, double want) {
    return std::abs(d - want) <= spec.spacing_tolerance_m;
  };
  std::vector<TrolleyDetection> found;
  std::vector<Eigen::Vector2d> centres;
  const size_t n = legs.size();
  for (size_t a = 0; a < n; ++a) {
    for (size_t b = 0; b < n; ++b) {
      for (size_t c = 0; c < n; ++c) {
        if (a == b || a == c || b == c) continue;
        const Eigen::Vector2d along = legs[b] - legs[a], across = legs[c] - legs[a];
        if (!matches(along.norm(), spec.leg_spacing_x_m) ||
            !matches(across.norm(), spec.leg_spacing_y_m)) {
          continue;
        }
        // Right angle within the tolerance over the shorter side.
        if (std::abs(along.normalized().dot(across.normalized())) >
            spec.spacing_tolerance_m / spec.leg_spacing_y_m) {
          continue;
        }
        const Eigen::Vector2d fourth = legs[b] + across;
        int seen = 3;
        for (size_t d = 0; d < n; ++d) {
          if (d != a && d != b && d != c && (legs[d] - fourth).norm() < spec.spacing_tolerance_m) {
            seen = 4;
          }
        }
        const Eigen::Vector2d centre = legs[a] + 0.5 * (along + across);
        bool duplicate = false;
        for (size_t k = 0; k < centres.size(); ++k) {
          if ((centres[k] - centre).norm() < spec.spacing_tolerance_m) {
            duplicate = true;
            found[k].legs_seen = std::max(found[k].legs_seen, seen);
          }
        }
        if (duplicate) continue;
        // x along the long side, pointing away from the robot (base_link origin).
        Eigen::Vector2d x_axis = along.normalized();
        if (x_axis.dot(centre) < 0.0) x_axis = -x_axis;
        centres.push_back(centre);
        found.push_back({Pose2(centre.x(), centre.y(), std::atan2(x_axis.y(), x_axis.x())), seen});
      }
    }
  }
  std::sort(found.begin(), found.end(), [](const TrolleyDetection& l, const TrolleyDetection& r) {
    return l.pose_in_base.translation().norm() < r.pose_in_base.translation().norm();
  });
  return found;
}

std::optional<LegGate> FindLegGate(const std::vector<Eigen::Vector2d>& legs,
                                   const Eigen::Vector2d& move_direction, const TrolleySpec& spec,
                                   double max_offset_m, double max_angle_rad) {
  const double reach_m = LegReachM(spec);
  std::optional<LegGate> best;
  double best_offset_m = max_offset_m;
  for (size_t i = 0; i < legs.size(); ++i) {
    for (size_t j = i + 1; j < legs.size(); ++j) {
      const Eigen::Vector2d& a = legs[i];
      const Eigen::Vector2d& b = legs[j];
      if (a.norm() > reach_m || b.norm() > reach_m) continue;
      const double spacing_m = (b - a).norm();
      if (std::abs(spacing_m - spec.leg_spacing_x_m) > spec.spacing_tolerance_m &&
          std::abs(spacing_m - spec.leg_spacing_y_m) > spec.spacing_tolerance_m) {
        continue;
      }
      const Eigen::Vector2d middle = 0.5 * (a + b);
      Eigen::Vector2d normal(-(b - a).y(), (b - a).x());
      normal.normalize();
      if (normal.dot(middle) < 0.0) normal = -normal;
      if (middle.dot(move_direction) <= 0.0 ||
          std::acos(std::clamp(normal.dot(move_direction), -1.0, 1.0)) > max_angle_rad) {
        continue;
      }
      // How far the middle lies off the move's line through the robot's centre.
      const double offset_m =
          std::abs(move_direction.x() * middle.y() - move_direction.y() * middle.x());
      if (offset_m < best_offset_m) {
        best_offset_m = offset_m;
        best = LegGate{middle, normal};
      }
    }
  }
  return best;
}

DockFrames DockFramesFor(const Pose2& trolley, const TrolleySpec& spec, const RobotModel& model,
                         double standoff_m) {
  double robot_front_m = 0.0;
  for (const Eigen::Vector2d& p : model.footprint_m) robot_front_m = std::max(robot_front_m, p.x());
  const double back_off =
      0.5 * spec.leg_spacing_x_m + spec.leg_radius_m + robot_front_m + standoff_m;
  return {trolley * Pose2(-back_off, 0.0, 0.0), trolley};
}

}  // namespace fleetnav::agent
