#include "fleetnav/planner/grid/body_clearance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fleetnav::planner {

BodyClearance::BodyClearance(const Costmap* costmap,
                             const std::vector<Eigen::Vector2d>& footprint_m)
    : costmap_(costmap) {
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  for (const Eigen::Vector2d& corner : footprint_m) {
    lo = lo.cwiseMin(corner);
    hi = hi.cwiseMax(corner);
  }
  const bool along_x = hi.x() - lo.x() >= hi.y() - lo.y();
  const double length_m = along_x ? hi.x() - lo.x() : hi.y() - lo.y();
  const double half_width_m = 0.5 * (along_x ? hi.y() - lo.y() : hi.x() - lo.x());
  // Pieces at most half as long as the body is wide: the discs round them stick out beside
  // the body by at most 12 % of its half width.
  const int n = std::max(1, static_cast<int>(std::ceil(length_m / half_width_m)));
  const double piece_m = length_m / n;
  radius_m_ = std::hypot(half_width_m, 0.5 * piece_m);
  const double start = (along_x ? lo.x() : lo.y()) + 0.5 * piece_m;
  const double across = along_x ? 0.5 * (lo.y() + hi.y()) : 0.5 * (lo.x() + hi.x());
  for (int k = 0; k < n; ++k) {
    const double along = start + k * piece_m;
    centres_in_base_.push_back(along_x ? Eigen::Vector2d(along, across)
                                       : Eigen::Vector2d(across, along));
  }
}

double BodyClearance::At(const Pose2& pose_in_grid) const {
  const double res = costmap_->resolution_m();
  double clearance = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector2d& centre : centres_in_base_) {
    const Eigen::Vector2d p = pose_in_grid.TransformPoint(centre);
    const int x = static_cast<int>(std::floor(p.x() / res));
    const int y = static_cast<int>(std::floor(p.y() / res));
    const double d = costmap_->InBounds(x, y) ? costmap_->DistanceToObstacle_m(x, y) : 0.0;
    clearance = std::min(clearance, d - radius_m_);
  }
  return clearance;
}

}  // namespace fleetnav::planner
