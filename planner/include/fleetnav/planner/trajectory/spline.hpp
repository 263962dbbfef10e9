#pragma once

#include <Eigen/Core>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/core/robot_model.hpp"

namespace fleetnav::planner {

/// A C²-continuous cubic spline through 2D knots, as in the KUKA omnidirectional-platform
/// thesis, ch. 10 (eqs. 10.1–10.14): chord-length parameters u_i ∈ [0, 1] (eq. 10.2), one
/// Hermite cubic per interval (eq. 10.12), end tangents given (eq. 10.14), and the interior
/// gradients P'_i solved from the C² conditions (eqs. 10.7–10.8) as one tridiagonal system.
/// Immutable; thread-compatible.
class CubicSpline {
 public:
  /// `start_direction` and `end_direction` are the wanted tangent directions (any length
  /// > 0; scaled to the polygon length). InvalidArgument for fewer than 2 knots, repeated
  /// consecutive knots or a zero direction.
  static absl::StatusOr<CubicSpline> Create(const std::vector<Eigen::Vector2d>& knots,
                                            const Eigen::Vector2d& start_direction,
                                            const Eigen::Vector2d& end_direction);
  Eigen::Vector2d Evaluate(double u) const;
  Eigen::Vector2d Derivative(double u) const;
  Eigen::Vector2d SecondDerivative(double u) const;
  const std::vector<double>& parameters() const { return u_; }
  /// Points at `points_per_metre` along the polygon length (at least the knots' count).
  std::vector<Eigen::Vector2d> Sample(double points_per_metre) const;

 private:
  int Segment(double u) const;
  std::vector<Eigen::Vector2d> p_;
  std::vector<Eigen::Vector2d> dp_;
  std::vector<double> u_;
  double length_m_ = 0.0;
};

/// End-point augmentation (KUKA thesis ch. 9): where the motion would turn back by more than
/// `max_turn_rad` at a knot — an omni platform going sideways and back, whose casters would
/// flip 180° at once — one extra knot is inserted after it, `radius_m` beyond it and to the
/// left, so that the spline through the knots bends through the turn instead of reversing
/// on the spot. The knot itself is still visited.
std::vector<Eigen::Vector2d> AugmentEndpoints(const std::vector<Eigen::Vector2d>& knots,
                                              double radius_m, double max_turn_rad);

/// One sample of a timed path.
struct TimedPose {
  double t_s = 0.0;
  Eigen::Vector2d position_m;
  double yaw_rad = 0.0;  ///< direction of travel
  double speed_mps = 0.0;
};

/// Time parameterisation of a sampled path under the model's limits: speed ≤ max_speed_mps,
/// yaw rate speed · curvature ≤ max_yaw_rate_radps, |acceleration| ≤ max_accel_mps2, at rest at
/// both ends. A forward pass bounds acceleration and a backward pass deceleration (the classic
/// two-pass velocity profile). InvalidArgument for fewer than 2 points or non-positive limits.
absl::StatusOr<std::vector<TimedPose>> TimeParameterize(const std::vector<Eigen::Vector2d>& path,
                                                        const MotionLimits& limits);

}  // namespace fleetnav::planner
