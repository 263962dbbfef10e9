// Fence navigation closed around a perfect unicycle and a geometric ultrasonic: the fence is
// the line y = 1.2 m on the robot's left, with a gap where it does not answer.
#include "fleetnav/robot_agent/control/modes/fence_following_controller.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "fleetnav/core/angles.hpp"
#include "kinematic_unicycle.hpp"

namespace fleetnav::agent {
namespace {

using testing::KinematicUnicycle;

constexpr double kDt = 0.02;
constexpr double kFenceYM = 1.2;

const SensorMount& LeftUltrasonic() {
  static const RobotModel kModel = LelyVectorModel();
  return *kModel.FindSensor("ultrasonic_left");
}

/// Range from the left ultrasonic to the fence along its beam; nullopt in the gap or when the
/// beam does not point at the fence.
std::optional<double> Ultrasonic(const Pose2& pose, double gap_from_x_m, double gap_to_x_m) {
  const Pose2 sensor = pose * LeftUltrasonic().pose_in_base;
  const double sin_beam = std::sin(sensor.yaw_rad());
  if (sin_beam < 0.5) return std::nullopt;
  const double range = (kFenceYM - sensor.y_m()) / sin_beam;
  const double hit_x = sensor.x_m() + range * std::cos(sensor.yaw_rad());
  if (range <= 0.0 || range > 2.5 || (hit_x >= gap_from_x_m && hit_x <= gap_to_x_m)) {
    return std::nullopt;
  }
  return range;
}

struct FenceRun {
  bool done = false;
  double max_error_after_settling_m = 0.0;
  double max_error_in_gap_m = 0.0;
  std::vector<NavigationMode> modes;
  std::vector<std::string> reasons;
  Pose2 end;
};

FenceRun Drive(const Pose2& start, double gap_from_x_m, double gap_to_x_m, double distance_m) {
  const FenceNavigationAction action{Side::kLeft, 0.95, distance_m, 0.3};
  FenceFollowingController controller(action, LeftUltrasonic(), MotionProfile{});
  KinematicUnicycle robot(start);
  FenceRun run;
  for (int step = 0; step < 20000; ++step) {
    ControlInput input = OdometryInput(robot.pose(), kDt);
    input.perception.fence_left_m = Ultrasonic(robot.pose(), gap_from_x_m, gap_to_x_m);
    const ControlOutput out = controller.Step(input);
    EXPECT_TRUE(out.failure.ok());
    if (out.done) {
      run.done = true;
      break;
    }
    if (run.modes.empty() || run.modes.back() != out.mode) run.modes.push_back(out.mode);
    if (!out.mode_reason.empty()) run.reasons.push_back(out.mode_reason);
    // The robot's line is where its sensor sits 0.95 m from the fence: y = 1.2 - 0.95 - 0.25.
    const double error = std::abs(robot.pose().y_m() - 0.0);
    const double x = robot.pose().x_m();
    if (x > 4.0) run.max_error_after_settling_m = std::max(run.max_error_after_settling_m, error);
    if (x > gap_from_x_m && x < gap_to_x_m) {
      run.max_error_in_gap_m = std::max(run.max_error_in_gap_m, error);
    }
    EXPECT_GE(out.command.vx_mps, 0.0);
    EXPECT_LE(out.command.vx_mps, 0.3 + 1e-9);
    robot.Step(out.command, kDt);
  }
  run.end = robot.pose();
  return run;
}

TEST(FenceFollowingControllerTest, ConvergesOntoTheFenceDistanceAndEndsAtTheDistance) {
  const FenceRun run = Drive(Pose2(0.0, -0.25, DegToRad(5)), 1e9, 1e9, 10.0);
  ASSERT_TRUE(run.done);
  EXPECT_LT(run.max_error_after_settling_m, 0.02);
  EXPECT_NEAR(run.end.x_m(), 10.0, 0.05);
  EXPECT_NEAR(RadToDeg(run.end.yaw_rad()), 0.0, 1.0);
  ASSERT_EQ(run.modes.size(), 1u);
  EXPECT_EQ(run.modes[0], NavigationMode::kFenceReactive);
}

// Through a 3 m gap the controller holds the fence line it measured, on the (here perfect)
// estimated pose, and resumes the reactive law once the fence answers.
TEST(FenceFollowingControllerTest, GapIsBridgedMapBasedAndReactiveResumes) {
  const FenceRun run = Drive(Pose2(0.0, 0.1, 0.0), 6.0, 9.0, 14.0);
  ASSERT_TRUE(run.done);
  EXPECT_LT(run.max_error_in_gap_m, 0.03);
  EXPECT_LT(run.max_error_after_settling_m, 0.03);
  ASSERT_EQ(run.modes.size(), 3u);
  EXPECT_EQ(run.modes[0], NavigationMode::kFenceReactive);
  EXPECT_EQ(run.modes[1], NavigationMode::kFenceMapBased);
  EXPECT_EQ(run.modes[2], NavigationMode::kFenceReactive);
  ASSERT_EQ(run.reasons.size(), 2u);
  EXPECT_NE(run.reasons[0].find("no echo from the left fence"), std::string::npos);
}

// Started 0.7 m further from the fence than its distance (where a robot that must turn in place
// can stand): the first echo places the fence, the robot closes in reactively and holds the
// line — it does not take the real fence for an outlier and steer on an imagined one.
TEST(FenceFollowingControllerTest, StartOffTheDistanceClosesInReactively) {
  const FenceRun run = Drive(Pose2(0.0, -0.7, 0.0), 1e9, 1e9, 12.0);
  ASSERT_TRUE(run.done);
  EXPECT_LT(run.max_error_after_settling_m, 0.03);
  ASSERT_EQ(run.modes.size(), 1u);
  EXPECT_EQ(run.modes[0], NavigationMode::kFenceReactive);
}

TEST(FenceFollowingControllerTest, ParamsAreValidated) {
  FenceFollowingParams params;
  EXPECT_TRUE(params.Validate().ok());
  params.gain_radps_per_m = 0.0;
  EXPECT_EQ(params.Validate().code(), absl::StatusCode::kInvalidArgument);
  params = {};
  params.lost_after_ticks = 0;
  EXPECT_EQ(params.Validate().code(), absl::StatusCode::kInvalidArgument);
  params = {};
  params.start_offset_m = -1.0;
  EXPECT_EQ(params.Validate().code(), absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace fleetnav::agent
