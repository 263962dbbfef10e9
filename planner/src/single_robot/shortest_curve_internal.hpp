#pragma once

// The analytic expansion of the lattice planner's search for car-like robots (Dolgov, Thrun,
// Montemerlo and Diebel 2010, hybrid A*): the shortest Reeds-Shepp (or, without reversing,
// Dubins) curve from a search node to the goal, sampled into poses.

#include <vector>

#include "fleetnav/core/pose2.hpp"

namespace fleetnav::planner::internal {

/// The poses along the shortest curve from `from` to `to` of minimum turning radius
/// `turning_radius_m` — Reeds-Shepp when `reverse` is allowed, Dubins otherwise — at most
/// `spacing_m` apart, the last one `to` itself. Empty when from and to coincide.
std::vector<Pose2> ShortestCurvePoses(const Pose2& from, const Pose2& to, double turning_radius_m,
                                      bool reverse, double spacing_m);

}  // namespace fleetnav::planner::internal
