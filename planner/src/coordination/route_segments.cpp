#include "fleetnav/planner/coordination/route_segments.hpp"

#include <cmath>

namespace fleetnav::planner {
namespace {

double DistanceM(const Pose2& a, const Pose2& b) {
  return (b.translation() - a.translation()).norm();
}

/// The direction of travel at poses[i]: from the pose about 0.3 m before it (the pose's own
/// yaw where it has not moved).
double TravelYaw(const std::vector<Pose2>& poses, size_t i) {
  constexpr double kBaselineM = 0.3;
  size_t j = i;
  while (j > 0 && DistanceM(poses[j], poses[i]) < kBaselineM) --j;
  const Eigen::Vector2d d = poses[i].translation() - poses[j].translation();
  return d.norm() > 1e-6 ? std::atan2(d.y(), d.x()) : poses[i].yaw_rad();
}

}  // namespace

std::vector<ActionSegment> SplitIntoSegments(const PredictedAction& action, double segment_m) {
  const std::vector<Pose2>& poses = action.poses;
  double length_m = 0.0;
  for (size_t i = 1; i < poses.size(); ++i) length_m += DistanceM(poses[i - 1], poses[i]);
  if (segment_m <= 0.0 || length_m < 1.5 * segment_m || poses.size() < 2) {
    return {ActionSegment{poses, action.duration_s, std::nullopt}};
  }
  std::vector<ActionSegment> out;
  ActionSegment current;
  current.poses.push_back(poses.front());
  double piece_m = 0.0;
  double done_m = 0.0;
  for (size_t i = 1; i < poses.size(); ++i) {
    const double step_m = DistanceM(poses[i - 1], poses[i]);
    piece_m += step_m;
    done_m += step_m;
    current.poses.push_back(poses[i]);
    if (piece_m >= segment_m && length_m - done_m >= 0.5 * segment_m) {
      current.duration_s = action.duration_s * piece_m / length_m;
      current.gate = Pose2(poses[i].x_m(), poses[i].y_m(), TravelYaw(poses, i));
      out.push_back(std::move(current));
      current = ActionSegment{};
      current.poses.push_back(poses[i]);
      piece_m = 0.0;
    }
  }
  current.duration_s = action.duration_s * piece_m / length_m;
  out.push_back(std::move(current));
  return out;
}

}  // namespace fleetnav::planner
