#include <ompl/base/spaces/DubinsStateSpace.h>
#include <ompl/base/spaces/ReedsSheppStateSpace.h>

#include <algorithm>
#include <cmath>

#include "shortest_curve_internal.hpp"

namespace fleetnav::planner::internal {

std::vector<Pose2> ShortestCurvePoses(const Pose2& from, const Pose2& to, double turning_radius_m,
                                      bool reverse, double spacing_m) {
  namespace ob = ompl::base;
  // The curve is computed once; interpolation then walks it.
  const auto sample = [&](const auto& space, auto curve, const ob::State* a, const ob::State* b,
                          ob::State* at) {
    std::vector<Pose2> poses;
    const double length_m = curve.length() * turning_radius_m;
    if (!(length_m > 1e-9)) return poses;
    const int n = std::max(1, static_cast<int>(std::ceil(length_m / spacing_m)));
    poses.reserve(static_cast<size_t>(n));
    bool first_time = false;  // the curve is given: OMPL does not compute it again
    for (int k = 1; k < n; ++k) {
      space.interpolate(a, b, static_cast<double>(k) / n, first_time, curve, at);
      const auto* se2 = at->template as<ob::SE2StateSpace::StateType>();
      poses.emplace_back(se2->getX(), se2->getY(), se2->getYaw());
    }
    poses.push_back(to);
    return poses;
  };
  const auto set = [](ob::State* state, const Pose2& pose) {
    auto* se2 = state->as<ob::SE2StateSpace::StateType>();
    se2->setXY(pose.x_m(), pose.y_m());
    se2->setYaw(pose.yaw_rad());
  };
  // Both spaces: the states, the curve (computed once by `curve_of`), its poses.
  const auto poses_in = [&](auto& space, const auto& curve_of) {
    ob::State* a = space.allocState();
    ob::State* b = space.allocState();
    ob::State* at = space.allocState();
    set(a, from);
    set(b, to);
    std::vector<Pose2> poses = sample(space, curve_of(space, a, b), a, b, at);
    for (ob::State* s : {a, b, at}) space.freeState(s);
    return poses;
  };
  if (reverse) {
    ob::ReedsSheppStateSpace space(turning_radius_m);
    return poses_in(space, [](const ob::ReedsSheppStateSpace& s, const ob::State* a,
                              const ob::State* b) { return s.reedsShepp(a, b); });
  }
  ob::DubinsStateSpace space(turning_radius_m);
  return poses_in(space, [](const ob::DubinsStateSpace& s, const ob::State* a, const ob::State* b) {
    return s.dubins(a, b);
  });
}

}  // namespace fleetnav::planner::internal
