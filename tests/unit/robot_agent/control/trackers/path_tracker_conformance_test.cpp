// What every PathTracker promises, whatever the drive kind: it reaches the goal of a path and
// stops there, never commands beyond its robot's motion limits, never commands NaN, and copes
// with a one-point path and with a path that reverses on itself. Each tracker drives an ideal
// body of its kind (a unicycle for differential and Ackermann, an omni body for mecanum).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/robot_agent/control/trackers/ackermann_pure_pursuit.hpp"
#include "fleetnav/robot_agent/control/trackers/holonomic_tracker.hpp"
#include "fleetnav/robot_agent/control/trackers/regulated_pure_pursuit.hpp"
#include "kinematic_unicycle.hpp"

namespace fleetnav::agent {
namespace {

constexpr double kDt = 0.05;
constexpr int kMaxSteps = 4000;  // 200 s

/// One tracker under test with the robot it drives.
struct DifferentialTracker {
  static RobotModel Model() { return LelyVectorModel(); }
  static std::unique_ptr<PathTracker> Make() {
    return std::make_unique<RegulatedPurePursuit>(RegulatedPurePursuitParams{}, Model().limits);
  }
  static Pose2 Move(const Pose2& pose, const Twist2& twist, double dt_s) {
    testing::KinematicUnicycle body(pose);
    body.Step(twist, dt_s);
    return body.pose();
  }
};

struct OmniTracker {
  static RobotModel Model() { return MecanumPlatformModel(); }
  static std::unique_ptr<PathTracker> Make() {
    return std::make_unique<HolonomicTracker>(HolonomicTrackerParams{}, Model().limits);
  }
  static Pose2 Move(const Pose2& pose, const Twist2& twist, double dt_s) {
    return testing::MovedOmni(pose, twist, dt_s);
  }
};

struct AckermannTracker {
  static RobotModel Model() { return AckermannDeliveryModel(); }
  static std::unique_ptr<PathTracker> Make() {
    return std::make_unique<AckermannPurePursuit>(AckermannPurePursuitParams{}, Model());
  }
  static Pose2 Move(const Pose2& pose, const Twist2& twist, double dt_s) {
    return DifferentialTracker::Move(pose, twist, dt_s);
  }
};

template <typename Kind>
class PathTrackerConformanceTest : public ::testing::Test {
 protected:
  struct Run {
    Pose2 end;
    bool done = false;
    bool finite = true;
    double max_forward_mps = 0.0;
    double max_reverse_mps = 0.0;
    double max_lateral_mps = 0.0;
    double max_yaw_rate_radps = 0.0;
    Twist2 last;
  };

  /// Drives `path` from `start` until the tracker is done (then one more tick) or time runs out.
  static Run Drive(const std::vector<Pose2>& path, const Pose2& start) {
    std::unique_ptr<PathTracker> tracker = Kind::Make();
    tracker->SetPath(path);
    Run run;
    Pose2 pose = start;
    for (int i = 0; i < kMaxSteps; ++i) {
      const bool was_done = tracker->done();
      const Twist2 twist = tracker->Step(pose, kDt);
      run.last = twist;
      run.finite = run.finite && std::isfinite(twist.vx_mps) && std::isfinite(twist.vy_mps) &&
                   std::isfinite(twist.yaw_rate_radps) && std::isfinite(tracker->remaining_m()) &&
                   std::isfinite(tracker->cross_track_m());
      if (!run.finite) break;
      run.max_forward_mps = std::max(run.max_forward_mps, twist.vx_mps);
      run.max_reverse_mps = std::max(run.max_reverse_mps, -twist.vx_mps);
      run.max_lateral_mps = std::max(run.max_lateral_mps, std::abs(twist.vy_mps));
      run.max_yaw_rate_radps = std::max(run.max_yaw_rate_radps, std::abs(twist.yaw_rate_radps));
      if (was_done) break;
      pose = Kind::Move(pose, twist, kDt);
    }
    run.end = pose;
    run.done = tracker->done();
    return run;
  }

  static void ExpectWithinLimits(const Run& run) {
    const MotionLimits limits = Kind::Model().limits;
    constexpr double kSlack = 1e-6;
    EXPECT_TRUE(run.finite);
    EXPECT_LE(run.max_forward_mps, limits.max_speed_mps + kSlack);
    EXPECT_LE(run.max_reverse_mps, limits.max_reverse_speed_mps + kSlack);
    EXPECT_LE(run.max_lateral_mps, limits.max_lateral_speed_mps + kSlack);
    EXPECT_LE(run.max_yaw_rate_radps, limits.max_yaw_rate_radps + kSlack);
  }

  static void ExpectStoppedAt(const Run& run, const Pose2& goal, double tolerance_m) {
    EXPECT_TRUE(run.done);
    EXPECT_LT((run.end.translation() - goal.translation()).norm(), tolerance_m);
    EXPECT_NEAR(run.last.vx_mps, 0.0, 1e-9);
    EXPECT_NEAR(run.last.vy_mps, 0.0, 1e-9);
    EXPECT_NEAR(run.last.yaw_rate_radps, 0.0, 1e-9);
  }
};

using TrackerKinds = ::testing::Types<DifferentialTracker, OmniTracker, AckermannTracker>;
TYPED_TEST_SUITE(PathTrackerConformanceTest, TrackerKinds);

std::vector<Pose2> Line(const Pose2& from, double length_m, double step_m = 0.05) {
  std::vector<Pose2> path;
  for (double s = 0.0; s <= length_m + 1e-9; s += step_m) {
    path.emplace_back(from.x_m() + s * std::cos(from.yaw_rad()),
                      from.y_m() + s * std::sin(from.yaw_rad()), from.yaw_rad());
  }
  return path;
}

TYPED_TEST(PathTrackerConformanceTest, ReachesTheGoalOfACurvedPathAndStops) {
  // A quarter circle of 3 m radius, wide enough for the Ackermann robot, then 2 m straight.
  std::vector<Pose2> path;
  for (double a = 0.0; a <= kPi / 2 + 1e-9; a += 0.02) {
    path.emplace_back(3.0 * std::sin(a), 3.0 - 3.0 * std::cos(a), a);
  }
  const std::vector<Pose2> on = Line(Pose2(3.0, 3.0, kPi / 2), 2.0);
  path.insert(path.end(), on.begin() + 1, on.end());
  const auto run = TestFixture::Drive(path, Pose2(0.0, 0.0, 0.0));
  TestFixture::ExpectWithinLimits(run);
  TestFixture::ExpectStoppedAt(run, path.back(), 0.2);
}

TYPED_TEST(PathTrackerConformanceTest, StartingOffThePathItStillEndsAtTheGoal) {
  const std::vector<Pose2> path = Line(Pose2(0.0, 0.0, 0.0), 6.0);
  const auto run = TestFixture::Drive(path, Pose2(0.0, 0.4, 0.2));
  TestFixture::ExpectWithinLimits(run);
  TestFixture::ExpectStoppedAt(run, path.back(), 0.2);
}

TYPED_TEST(PathTrackerConformanceTest, AOnePointPathIsItsOwnGoal) {
  const Pose2 goal(2.0, 0.0, 0.0);
  const auto ahead = TestFixture::Drive({goal}, Pose2(0.0, 0.0, 0.0));
  TestFixture::ExpectWithinLimits(ahead);
  TestFixture::ExpectStoppedAt(ahead, goal, 0.2);
  // Standing on it already: done at once, without moving.
  const auto there = TestFixture::Drive({goal}, goal);
  TestFixture::ExpectWithinLimits(there);
  TestFixture::ExpectStoppedAt(there, goal, 1e-6);
}

TYPED_TEST(PathTrackerConformanceTest, APathThatReversesEndsAtItsGoal) {
  // 3 m east, then a cusp: 2 m backwards to the north-west, still facing east-south-east (the
  // way a car backs out). Robots that may reverse back up; the others turn round as their
  // kinematics allow. The goal is off the first leg, so it cannot be met on the way out.
  std::vector<Pose2> path = Line(Pose2(0.0, 0.0, 0.0), 3.0);
  const double back_yaw = std::atan2(-1.0, 1.5);  // facing away from the way it moves
  for (double s = 0.05; s <= std::hypot(1.5, 1.0) + 1e-9; s += 0.05) {
    path.emplace_back(3.0 - s * std::cos(back_yaw), -s * std::sin(back_yaw), back_yaw);
  }
  const auto run = TestFixture::Drive(path, Pose2(0.0, 0.0, 0.0));
  TestFixture::ExpectWithinLimits(run);
  TestFixture::ExpectStoppedAt(run, path.back(), 0.3);
}

}  // namespace
}  // namespace fleetnav::agent
