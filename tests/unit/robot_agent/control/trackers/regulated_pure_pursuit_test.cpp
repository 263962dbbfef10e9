#include "fleetnav/robot_agent/control/trackers/regulated_pure_pursuit.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "kinematic_unicycle.hpp"

namespace fleetnav::agent {
namespace {

using testing::KinematicUnicycle;

constexpr double kDt = 0.02;
constexpr double kStepM = 0.075;  // the lattice's straight primitive on a 5 cm map

// A lattice path for a robot that turns in place: straight east for `first_m`, a turn in place
// at that place by `turn_deg` in steps of 22.5 degrees, then straight on for `then_m`.
std::vector<Pose2> StraightTurnStraight(double first_m, double turn_deg, double then_m) {
  std::vector<Pose2> path;
  for (double x = 0.0; x <= first_m + 1e-9; x += kStepM) path.emplace_back(x, 0.0, 0.0);
  const double corner_x = path.back().x_m();
  const int steps = static_cast<int>(std::round(std::abs(turn_deg) / 22.5));
  for (int k = 1; k <= steps; ++k) {
    path.emplace_back(corner_x, 0.0, DegToRad(std::copysign(22.5 * k, turn_deg)));
  }
  const double yaw = path.back().yaw_rad();
  for (double s = kStepM; s <= then_m + 1e-9; s += kStepM) {
    path.emplace_back(corner_x + s * std::cos(yaw), s * std::sin(yaw), yaw);
  }
  return path;
}

struct TrackedRun {
  double x_when_turning_m = -1.0;  // where the heading first left the first leg's by 5 degrees
  double slowest_on_first_leg_mps = 1e9;  // the least forward speed once under way, first leg
  bool done = false;
};

TrackedRun Track(const std::vector<Pose2>& path) {
  RegulatedPurePursuitParams params;
  params.desired_speed_mps = 0.3;
  RegulatedPurePursuit tracker(params, LelyVectorModel().limits);
  tracker.SetPath(path);
  KinematicUnicycle robot(path.front());
  TrackedRun run;
  bool under_way = false;
  for (int i = 0; i < 20000 && !tracker.done(); ++i) {
    const Twist2 command = tracker.Step(robot.pose(), kDt);
    robot.Step(command, kDt);
    if (run.x_when_turning_m < 0.0) {
      if (std::abs(robot.unwrapped_yaw_rad()) > DegToRad(5.0)) {
        run.x_when_turning_m = robot.pose().x_m();
      } else if (command.vx_mps > 0.2) {
        under_way = true;
      } else if (under_way) {
        run.slowest_on_first_leg_mps = std::min(run.slowest_on_first_leg_mps, command.vx_mps);
      }
    }
  }
  run.done = tracker.done();
  return run;
}

TEST(RegulatedPurePursuitTest, ASharpTurnInPlaceIsTurnedWhereThePlanTurns) {
  // The barn case: along a fence lane, then a turn of 112.5 degrees in place at the lane's end.
  // Looking past the turn, the robot had turned 0.45 m early and swung its tail into the fence.
  const std::vector<Pose2> path = StraightTurnStraight(3.0, -112.5, 1.5);
  const double corner_x = path[static_cast<size_t>(std::round(3.0 / kStepM))].x_m();
  const TrackedRun run = Track(path);
  EXPECT_TRUE(run.done);
  EXPECT_NEAR(run.x_when_turning_m, corner_x, 0.06);
}

TEST(RegulatedPurePursuitTest, AShallowKinkIsRoundedWithoutStopping) {
  // A turn of one heading bin (22.5 degrees) is below rotate_to_heading_rad: no stop there.
  const std::vector<Pose2> path = StraightTurnStraight(3.0, 22.5, 2.0);
  const TrackedRun run = Track(path);
  EXPECT_TRUE(run.done);
  EXPECT_GT(run.slowest_on_first_leg_mps, 0.1);
}

TEST(RegulatedPurePursuitTest, AHalfTurnAtTheGoalGoesTheWayThePlanTurnsIt) {
  // The lattice's last piece ran a bin south of west (-157.5 degrees) and the planner turns onto
  // the goal's yaw (east) from there in one step counter-clockwise, the sweep it checked. The
  // robot, having rounded the kink before, stands at the place still nearly facing west, where
  // the shortest way to east is clockwise: that way swung the Lely's nose into a fence.
  for (const double arrival_deg : {170.0, 175.0, 179.0}) {
    const std::vector<Pose2> path = {Pose2(0.0, 0.0, DegToRad(-157.5)), Pose2(0.0, 0.0, 0.0)};
    RegulatedPurePursuit tracker(RegulatedPurePursuitParams{}, LelyVectorModel().limits);
    tracker.SetPath(path);
    KinematicUnicycle robot(Pose2(0.01, 0.0, DegToRad(arrival_deg)));
    for (int i = 0; i < 20000 && !tracker.done(); ++i) {
      robot.Step(tracker.Step(robot.pose(), kDt), kDt);
    }
    ASSERT_TRUE(tracker.done()) << arrival_deg;
    // Facing east, having turned counter-clockwise (360 - arrival degrees), not clockwise.
    EXPECT_NEAR(robot.unwrapped_yaw_rad(), 2.0 * kPi, 0.05) << arrival_deg;
  }
}

}  // namespace
}  // namespace fleetnav::agent
