#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "fleetnav/core/route.hpp"
#include "fleetnav/core/stripe_marker.hpp"
#include "fleetnav/robot_agent/control/common/line_memory.hpp"
#include "fleetnav/robot_agent/control/common/motion_controller.hpp"
#include "fleetnav/robot_agent/control/common/stripe_path.hpp"
#include "fleetnav/robot_agent/control/modes/motion_controllers.hpp"

namespace fleetnav::agent {

struct StripeFollowingParams {
  /// Yaw rate per metre of lateral stripe offset at the inductive sensors, a look-ahead of
  /// 0.485 m on the Lely: e'' + L·k·e' + v·k·e = 0 has ζ ≈ 0.6 at 0.25 m/s for k = 1.5.
  double gain_radps_per_m = 1.5;
  double max_yaw_rate_radps = 0.3;
  /// Ticks without a reading before map-based fallback, and with readings before reactive again.
  int lost_after_ticks = 3;
  int found_after_ticks = 5;
  /// Travel over which stripe points are kept for the fitted stripe line.
  double line_memory_m = 3.0;
  /// The stripe counts as ended (not interrupted) when its reading is lost within this distance
  /// of an end of the stripe in the marker set: the estimate's along-track error between two
  /// markers, not the sensor's, sets it.
  double end_tolerance_m = 0.8;
  /// An interruption is bridged map-based for at most this far; then the leg fails.
  double max_interruption_m = 3.0;
  /// Without the stripe in the marker set, a loss this long is taken as its end.
  double unknown_end_after_m = 0.3;
  /// A leg may start this far before its stripe (a straight before it came up short on a
  /// slippery floor); no reading by then fails the leg.
  double search_m = 1.0;
  /// On curves the sensor's speed along the stripe is held to this share of max_yaw_rate_radps
  /// times the radius (the rest is left to the lateral correction), from this far ahead.
  double curve_yaw_share = 0.7;
  double curve_lookahead_m = 0.3;
  /// The sensor point is steered along the known stripe (not by the P law alone) where the
  /// stripe within a sensor lead behind and curve_lookahead_m ahead curves more than this, or
  /// while the robot's heading is further than straight_heading_rad off the stripe.
  double straight_curvature_per_m = 0.05;
  double straight_heading_rad = 0.06;
  absl::Status Validate() const;
};

/// Stripe navigation (Lely thesis §6.6.4, Fig. 6.14): a P law on the lateral offset that the
/// inductive sensors read of the stripe under them. The marker set's pieces (kind follow_stripe /
/// charger_stripe, joined by stripe_id) are chained with the stripes joined to them end to end
/// (StripePath): the sensor cannot tell where one stripe ends and the arc joined to it begins,
/// so the leg follows through joints. Near a curve the sensor point (L = 0.485 m ahead of the
/// axle on the Lely) is steered along the known stripe by feedback linearization — its velocity
/// the stripe's tangent at speed s plus the lateral correction, made with v = ṡ·h and
/// ω = ṡ·h⊥ / L — so it stays on a 0.5 m arc while the robot turns almost in place (s slowed
/// ahead of the curve so the turn stays within the yaw-rate limit). Where the reading is lost, the
/// chained pieces tell an end from an interruption: near one of the path's ends the stripe has
/// ended (the action is done when it ends on stripe_end); elsewhere the robot goes on map-based, on
/// the estimated pose, along the known path (or, without a marker set, along the line fitted
/// through the stripe points it measured), until the stripe answers again. A distance of 0 runs
/// until the end condition. Not thread-safe.
class StripeFollowingController : public MotionController {
 public:
  /// `stripe_pieces`: the marker set's pieces of this kind (may be empty); those of the action's
  /// stripe and of the stripes joined to it are followed.
  StripeFollowingController(const StripeNavigationAction& action, EndConditionKind end,
                            std::vector<StripeMarker> stripe_pieces, MotionProfile profile,
                            StripeFollowingParams params = {},
                            NavigationMode reactive_mode = NavigationMode::kStripeReactive,
                            NavigationMode map_based_mode = NavigationMode::kStripeMapBased);
  ControlOutput Step(const ControlInput& input) override;

 private:
  /// Distance from `point` (the sensor this tick) to the nearest end of the stripe (infinity
  /// when unknown); 0 once the sensor's foot on the chained stripe is an end.
  double DistanceToStripeEnd(const Eigen::Vector2d& point) const;
  /// The line map-based fallback steers on near `point`.
  void FallbackLine(const Eigen::Vector2d& point, Eigen::Vector2d* on_line,
                    Eigen::Vector2d* direction) const;

  StripeNavigationAction action_;
  EndConditionKind end_;
  std::vector<StripeMarker> pieces_;
  std::optional<StripePath> path_;
  std::optional<StripePath::Foot> foot_;  ///< of the sensor's estimate this tick
  std::vector<Eigen::Vector2d> ends_;
  MotionProfile profile_;
  StripeFollowingParams params_;
  NavigationMode reactive_mode_;
  NavigationMode map_based_mode_;
  bool started_ = false;
  bool seen_ = false;
  Pose2 last_odom_;
  double travelled_m_ = 0.0;
  double lost_since_m_ = 0.0;
  double last_speed_mps_ = 0.0;
  bool map_based_ = false;
  int missing_ticks_ = 0;
  int present_ticks_ = 0;
  LineMemory line_;
};

}  // namespace fleetnav::agent
