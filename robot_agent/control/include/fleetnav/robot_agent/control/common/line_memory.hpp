#pragma once

#include <Eigen/Core>
#include <deque>

namespace fleetnav::agent {

/// A straight feature that a reactive mode follows (a fence, a floor stripe), remembered in the
/// map: the points its sensor placed there with the localizer's pose over the last `memory_m`
/// of travel, and the least-squares line through them (principal axis), oriented along the
/// robot's heading. Until enough points span enough travel the assumed line holds. This is what
/// map-based fallback steers on where the feature is missing. Value type.
class LineMemory {
 public:
  explicit LineMemory(double memory_m) : memory_m_(memory_m) {}

  /// The line assumed before anything was measured.
  void Assume(const Eigen::Vector2d& point, const Eigen::Vector2d& direction);
  /// Adds a measured point at `travelled_m` of travel and refits.
  void Add(const Eigen::Vector2d& point_in_map, double travelled_m, const Eigen::Vector2d& heading);

  const Eigen::Vector2d& point() const { return point_; }
  const Eigen::Vector2d& direction() const { return direction_; }
  /// Signed distance of `p` from the line, positive on the left of its direction.
  double SignedDistance(const Eigen::Vector2d& p) const;

 private:
  struct Sample {
    Eigen::Vector2d point;
    double travelled_m = 0.0;
  };
  void Fit(const Eigen::Vector2d& heading);

  double memory_m_;
  std::deque<Sample> samples_;
  Eigen::Vector2d point_ = Eigen::Vector2d::Zero();
  Eigen::Vector2d direction_ = Eigen::Vector2d::UnitX();
};

}  // namespace fleetnav::agent
