// Stripe navigation closed around a perfect unicycle and a geometric inductive pair: the
// stripe runs along y = 0 from x = -1 to x = 12 and is interrupted for x in [4, 5.5].
#include "fleetnav/robot_agent/control/modes/stripe_following_controller.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "fleetnav/core/angles.hpp"
#include "kinematic_unicycle.hpp"

namespace fleetnav::agent {
namespace {

using testing::KinematicUnicycle;

constexpr double kDt = 0.02;
constexpr double kSensorXM = 0.485;  // the Lely's inductive pair ahead of the axle

StripeMarker Piece() {
  StripeMarker piece;
  piece.id = 10;
  piece.position_m = Eigen::Vector2d(5.5, 0.0);
  piece.length_m = 13.0;
  piece.kind = MarkerKind::kFollowStripe;
  piece.stripe_id = 1;
  return piece;
}

/// Where the stripe crosses the sensors' lateral line, in base_link y; nullopt off the stripe
/// or in the interruption.
std::optional<double> StripeOffset(const Pose2& pose) {
  const Pose2 sensor = pose * Pose2(kSensorXM, 0.0, 0.0);
  const double s = std::cos(sensor.yaw_rad());
  const double t = -sensor.y_m() / s;  // along the lateral line (-sin, cos) to y = 0
  const double x = sensor.x_m() - t * std::sin(sensor.yaw_rad());
  if (std::abs(t) > 0.15 || x < -1.0 || x > 12.0 || (x >= 4.0 && x <= 5.5)) return std::nullopt;
  return t;
}

struct StripeRun {
  bool done = false;
  absl::Status failure;
  Pose2 end;
  double max_lateral_m = 0.0;
  std::vector<NavigationMode> modes;
};

StripeRun Drive(const StripeNavigationAction& action, EndConditionKind end, const Pose2& start,
                std::vector<StripeMarker> pieces) {
  StripeFollowingController controller(action, end, std::move(pieces), MotionProfile{});
  KinematicUnicycle robot(start);
  StripeRun run;
  for (int step = 0; step < 20000; ++step) {
    ControlInput input = OdometryInput(robot.pose(), kDt);
    input.perception.stripe_sensor_x_m = kSensorXM;
    input.perception.stripe_offset_m = StripeOffset(robot.pose());
    const ControlOutput out = controller.Step(input);
    if (!out.failure.ok()) {
      run.failure = out.failure;
      break;
    }
    if (out.done) {
      run.done = true;
      break;
    }
    if (run.modes.empty() || run.modes.back() != out.mode) run.modes.push_back(out.mode);
    if (robot.pose().x_m() > 1.0) {
      run.max_lateral_m = std::max(run.max_lateral_m, std::abs(robot.pose().y_m()));
    }
    robot.Step(out.command, kDt);
  }
  run.end = robot.pose();
  return run;
}

TEST(StripeFollowingControllerTest, FollowsAcrossTheInterruptionToTheStripesEnd) {
  const StripeRun run = Drive(StripeNavigationAction{1, 0.0, 0.25}, EndConditionKind::kStripeEnd,
                              Pose2(0.0, 0.06, DegToRad(4)), {Piece()});
  ASSERT_TRUE(run.failure.ok()) << run.failure;
  ASSERT_TRUE(run.done);
  EXPECT_LT(run.max_lateral_m, 0.02);
  // Ended where the sensors ran off the stripe's end at x = 12 (not at the interruption).
  EXPECT_NEAR(run.end.x_m() + kSensorXM, 12.0, 0.35);
  ASSERT_EQ(run.modes.size(), 3u);
  EXPECT_EQ(run.modes[1], NavigationMode::kStripeMapBased);
}

// Slipping wheels run the estimate ahead: the stripe's end then lies behind the estimated
// sensor, and a loss there is still the end, not an interruption to drive on through.
TEST(StripeFollowingControllerTest, EstimateRunAheadPastTheEndStillEnds) {
  StripeFollowingController controller(StripeNavigationAction{1, 0.0, 0.25},
                                       EndConditionKind::kStripeEnd, {Piece()}, MotionProfile{});
  KinematicUnicycle robot(Pose2(10.0, 0.0, 0.0));
  const Pose2 run_ahead(1.5, 0.0, 0.0);  // the estimate is 1.5 m ahead of the truth
  bool done = false;
  for (int step = 0; step < 3000 && !done; ++step) {
    ControlInput input = OdometryInput(robot.pose(), kDt);
    input.pose_in_map = run_ahead * robot.pose();
    input.perception.stripe_sensor_x_m = kSensorXM;
    input.perception.stripe_offset_m = StripeOffset(robot.pose());
    const ControlOutput out = controller.Step(input);
    ASSERT_TRUE(out.failure.ok()) << out.failure;
    ASSERT_NE(out.mode, NavigationMode::kStripeMapBased) << "took the end for an interruption";
    done = out.done;
    robot.Step(out.command, kDt);
  }
  EXPECT_TRUE(done);
  EXPECT_NEAR(robot.pose().x_m() + kSensorXM, 12.0, 0.2);
}

// Without the stripe's geometry, an interruption cannot be told from the end: the leg ends
// at the interruption.
TEST(StripeFollowingControllerTest, WithoutTheMarkerSetALossIsTheEnd) {
  const StripeRun run = Drive(StripeNavigationAction{1, 0.0, 0.25}, EndConditionKind::kStripeEnd,
                              Pose2(0.0, 0.0, 0.0), {});
  ASSERT_TRUE(run.done);
  EXPECT_NEAR(run.end.x_m() + kSensorXM, 4.0, 0.4);
}

TEST(StripeFollowingControllerTest, DistanceEndsTheLegAndAnEarlyEndFailsIt) {
  StripeRun run = Drive(StripeNavigationAction{1, 2.5, 0.25}, EndConditionKind::kDistance,
                        Pose2(0.0, 0.0, 0.0), {Piece()});
  ASSERT_TRUE(run.done);
  EXPECT_NEAR(run.end.x_m(), 2.5, 0.01);
  run = Drive(StripeNavigationAction{1, 20.0, 0.25}, EndConditionKind::kDistance,
              Pose2(0.0, 0.0, 0.0), {Piece()});
  EXPECT_FALSE(run.done);
  EXPECT_NE(run.failure.message().find("stripe 1 ended"), std::string::npos) << run.failure;
}

TEST(StripeFollowingControllerTest, NoStripeUnderTheSensorsFails) {
  // 3 m beside the stripe: no reading within the 1 m search.
  const StripeRun run = Drive(StripeNavigationAction{1, 5.0, 0.25}, EndConditionKind::kDistance,
                              Pose2(0.0, 3.0, 0.0), {Piece()});
  EXPECT_FALSE(run.done);
  EXPECT_LT(run.end.x_m(), 1.1);
  EXPECT_NE(run.failure.message().find("no stripe under the inductive sensors"), std::string::npos);
}

}  // namespace
}  // namespace fleetnav::agent
