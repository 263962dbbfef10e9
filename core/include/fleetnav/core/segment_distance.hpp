#pragma once

#include <Eigen/Core>
#include <algorithm>

namespace fleetnav {

/// The distance from point `p` to the segment a–b (to `a` when the segment has no length).
inline double PointSegmentDistance(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                                   const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double length_sq = ab.squaredNorm();
  const double t = length_sq > 0.0 ? std::clamp((p - a).dot(ab) / length_sq, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

}  // namespace fleetnav
