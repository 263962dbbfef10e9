#include "fleetnav/planner/coordination/route_segments.hpp"

#include <algorithm>
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

std::vector<ActionSegment> SplitIntoSegments(const PredictedAction& action, double segment_m,
                                             const std::vector<Eigen::Vector2d>& stops) {
  const std::vector<Pose2>& poses = action.poses;
  double length_m = 0.0;
  for (size_t i = 1; i < poses.size(); ++i) length_m += DistanceM(poses[i - 1], poses[i]);
  // The pose nearest each stop, each after the one before (not the first pose, nor the last).
  std::vector<bool> cut_at(poses.size(), false);
  size_t from = 1;
  for (const Eigen::Vector2d& stop : stops) {
    size_t nearest = 0;
    for (size_t i = from; i + 1 < poses.size(); ++i) {
      if (nearest == 0 ||
          (poses[i].translation() - stop).norm() < (poses[nearest].translation() - stop).norm()) {
        nearest = i;
      }
    }
    if (nearest == 0) break;
    cut_at[nearest] = true;
    from = nearest + 1;
  }
  const bool any_cut = std::find(cut_at.begin(), cut_at.end(), true) != cut_at.end();
  if (segment_m <= 0.0 || poses.size() < 2 || length_m <= 1e-9 ||
      (length_m < 1.5 * segment_m && !any_cut)) {
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
    if (cut_at[i] || (piece_m >= segment_m && length_m - done_m >= 0.5 * segment_m &&
                      length_m >= 1.5 * segment_m)) {
      current.duration_s = action.duration_s * piece_m / length_m;
      current.gate = Pose2(poses[i].x_m(), poses[i].y_m(), TravelYaw(poses, i));
      current.ends_at_stop = cut_at[i];
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
