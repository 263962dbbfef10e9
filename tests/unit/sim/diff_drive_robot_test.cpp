// Fidelity of the simulated Lely Vector (thesis ch. 3: 1485 kg, wheels Ø 300 mm, track 0.92 m):
// the heavy body tracks a commanded twist in steady state and stays upright.
#include "fleetnav/sim/diff_drive_robot.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/sim/simulation.hpp"
#include "sim_test_util.hpp"

namespace fleetnav::sim {
namespace {

using testing::MakeSimulation;
using testing::TwistCommand;

constexpr double kPeriodS = 0.02;  // the default control period

struct Trace {
  std::vector<RobotTruth> truth;  ///< one per tick, after the tick
  double min_up_z = 1.0;
};

// Commands a constant twist and records the ground truth after every tick.
Trace Drive(Simulation& sim, const std::string& robot_id, double vx_mps, double yaw_rate_radps,
            double duration_s) {
  Trace trace;
  EXPECT_TRUE(sim.Command(robot_id, TwistCommand(vx_mps, yaw_rate_radps)).ok());
  const int ticks = static_cast<int>(std::lround(duration_s / kPeriodS));
  for (int i = 0; i < ticks; ++i) {
    sim.Advance();
    const GroundTruthSnapshot snapshot = sim.GroundTruth();
    EXPECT_EQ(snapshot.robots.size(), 1u);
    trace.truth.push_back(snapshot.robots.at(0));
    trace.min_up_z = std::min(trace.min_up_z, snapshot.robots.at(0).up_z);
  }
  return trace;
}

struct SteadyState {
  double speed_mps = 0.0;       ///< path length / time
  double yaw_rate_radps = 0.0;  ///< unwrapped heading change / time
  double mean_reported_speed_mps = 0.0;
  double mean_reported_yaw_rate_radps = 0.0;
};

// Measures over the ticks [from, end) of the trace.
SteadyState Measure(const Trace& trace, size_t from) {
  SteadyState out;
  double path_m = 0.0, turned_rad = 0.0;
  for (size_t i = from + 1; i < trace.truth.size(); ++i) {
    const Pose2& a = trace.truth[i - 1].pose;
    const Pose2& b = trace.truth[i].pose;
    path_m += (b.translation() - a.translation()).norm();
    turned_rad += AngleDifference(b.yaw_rad(), a.yaw_rad());
  }
  const double duration_s = static_cast<double>(trace.truth.size() - 1 - from) * kPeriodS;
  out.speed_mps = path_m / duration_s;
  out.yaw_rate_radps = turned_rad / duration_s;
  for (size_t i = from; i < trace.truth.size(); ++i) {
    out.mean_reported_speed_mps += trace.truth[i].velocity.vx_mps;
    out.mean_reported_yaw_rate_radps += trace.truth[i].velocity.yaw_rate_radps;
  }
  out.mean_reported_speed_mps /= static_cast<double>(trace.truth.size() - from);
  out.mean_reported_yaw_rate_radps /= static_cast<double>(trace.truth.size() - from);
  return out;
}

std::unique_ptr<Simulation> LelyAtOrigin() {
  std::unique_ptr<Simulation> sim = MakeSimulation(11);
  EXPECT_TRUE(sim->AddRobot("lely1", "lely-vector", Pose2(0, 0, 0)).ok());
  return sim;
}

TEST(LelyFidelityTest, StraightTwistTrackedWithinFivePercent) {
  std::unique_ptr<Simulation> sim = LelyAtOrigin();
  const Trace trace = Drive(*sim, "lely1", 0.25, 0.0, 20.0);
  const SteadyState steady = Measure(trace, trace.truth.size() / 2);  // the last 10 s
  std::printf(
      "[ figures  ] straight v=0.25: speed %.4f m/s (%.2f %%), yaw rate %.5f rad/s, "
      "min up_z %.5f\n",
      steady.speed_mps, 100.0 * (steady.speed_mps / 0.25 - 1.0), steady.yaw_rate_radps,
      trace.min_up_z);
  EXPECT_NEAR(steady.speed_mps, 0.25, 0.05 * 0.25);
  EXPECT_NEAR(steady.mean_reported_speed_mps, 0.25, 0.05 * 0.25);
  // Commanded ω = 0: within 5 % of the speed's equivalent over the track (≈ 0.3°/s).
  EXPECT_LT(std::abs(steady.yaw_rate_radps), 0.05 * 0.25 / 0.92 * 0.5);
  EXPECT_GT(trace.min_up_z, 0.95);
  // It went forward along +x and about 5 m in 20 s (the start ramps up).
  const Pose2& end = trace.truth.back().pose;
  EXPECT_NEAR(end.x_m(), 5.0, 0.25);
  EXPECT_LT(std::abs(end.y_m()), 0.05);
}

TEST(LelyFidelityTest, ArcTwistTrackedWithinFivePercent) {
  std::unique_ptr<Simulation> sim = LelyAtOrigin();
  const Trace trace = Drive(*sim, "lely1", 0.2, 0.2, 20.0);
  const SteadyState steady = Measure(trace, trace.truth.size() / 2);
  std::printf(
      "[ figures  ] arc v=0.2 w=0.2: speed %.4f m/s (%.2f %%), yaw rate %.4f rad/s "
      "(%.2f %%), min up_z %.5f\n",
      steady.speed_mps, 100.0 * (steady.speed_mps / 0.2 - 1.0), steady.yaw_rate_radps,
      100.0 * (steady.yaw_rate_radps / 0.2 - 1.0), trace.min_up_z);
  EXPECT_NEAR(steady.speed_mps, 0.2, 0.05 * 0.2);
  EXPECT_NEAR(steady.yaw_rate_radps, 0.2, 0.05 * 0.2);
  EXPECT_NEAR(steady.mean_reported_speed_mps, 0.2, 0.05 * 0.2);
  EXPECT_NEAR(steady.mean_reported_yaw_rate_radps, 0.2, 0.05 * 0.2);
  EXPECT_GT(trace.min_up_z, 0.95);
  // A circle of radius v/ω = 1 m about (0, 1): every steady-state pose lies on it.
  for (size_t i = trace.truth.size() / 2; i < trace.truth.size(); ++i) {
    const double radius = (trace.truth[i].pose.translation() - Eigen::Vector2d(0, 1)).norm();
    ASSERT_NEAR(radius, 1.0, 0.05) << "tick " << i;
  }
}

TEST(LelyFidelityTest, TurnInPlaceTracked) {
  std::unique_ptr<Simulation> sim = LelyAtOrigin();
  const Trace trace = Drive(*sim, "lely1", 0.0, -0.3, 10.0);
  const SteadyState steady = Measure(trace, trace.truth.size() / 2);
  EXPECT_NEAR(steady.yaw_rate_radps, -0.3, 0.05 * 0.3);
  EXPECT_GT(trace.min_up_z, 0.95);
  // Turning about the axle centre: base_link stays close to where it was.
  EXPECT_LT(trace.truth.back().pose.translation().norm(), 0.05);
}

TEST(LelyFidelityTest, ZeroCommandStaysPut) {
  std::unique_ptr<Simulation> sim = MakeSimulation(5);
  const Pose2 start(2.0, -1.0, DegToRad(30));
  ASSERT_TRUE(sim->AddRobot("lely1", "lely-vector", start).ok());
  const Trace trace = Drive(*sim, "lely1", 0.0, 0.0, 10.0);
  const Pose2 end = trace.truth.back().pose;
  std::printf("[ figures  ] zero command: drift %.6f m, %.6f deg over 10 s\n",
              (end.translation() - start.translation()).norm(),
              RadToDeg(AngleDifference(end.yaw_rad(), start.yaw_rad())));
  EXPECT_LT((end.translation() - start.translation()).norm(), 0.01);
  EXPECT_LT(std::abs(AngleDifference(end.yaw_rad(), start.yaw_rad())), DegToRad(0.5));
  for (const RobotTruth& truth : trace.truth) {
    ASSERT_LT((truth.pose.translation() - start.translation()).norm(), 0.01);
  }
  EXPECT_GT(trace.min_up_z, 0.95);
}

TEST(LelyFidelityTest, StopsWhenCommandedZeroAfterDriving) {
  std::unique_ptr<Simulation> sim = LelyAtOrigin();
  Drive(*sim, "lely1", 0.5, 0.0, 6.0);
  Drive(*sim, "lely1", 0.0, 0.0, 2.0);  // 1.5 t at 0.5 m/s needs a moment to stop
  const Trace still = Drive(*sim, "lely1", 0.0, 0.0, 5.0);
  EXPECT_LT((still.truth.back().pose.translation() - still.truth.front().pose.translation()).norm(),
            0.01);
  EXPECT_GT(still.min_up_z, 0.95);
}

TEST(DiffDriveRobotTest, SpawnPoseIsTheGroundTruthPose) {
  std::unique_ptr<Simulation> sim = MakeSimulation(1);
  const Pose2 start(-5.5, 3.0, DegToRad(-120));
  ASSERT_TRUE(sim->AddRobot("lely1", "lely-vector", start).ok());
  const GroundTruthSnapshot before = sim->GroundTruth();
  ASSERT_EQ(before.robots.size(), 1u);
  EXPECT_TRUE(before.robots[0].pose.IsNear(start, 1e-9, 1e-9))
      << before.robots[0].pose.DebugString();
  EXPECT_NEAR(before.robots[0].up_z, 1.0, 1e-9);
}

TEST(DiffDriveRobotTest, WheelSpeedCommandDrivesForward) {
  std::unique_ptr<Simulation> sim = LelyAtOrigin();
  ActuatorCommand command;
  command.drive = WheelSpeeds{0.2 / 0.15, 0.2 / 0.15};  // 0.2 m/s on Ø 300 mm wheels
  ASSERT_TRUE(sim->Command("lely1", command).ok());
  for (int i = 0; i < 250; ++i) sim->Advance();
  const RobotTruth truth = sim->GroundTruth().robots.at(0);
  EXPECT_NEAR(truth.velocity.vx_mps, 0.2, 0.01);
  EXPECT_GT(truth.pose.x_m(), 0.8);
}

TEST(DiffDriveRobotTest, AckermannCommandRejected) {
  std::unique_ptr<Simulation> sim = LelyAtOrigin();
  ActuatorCommand command;
  command.drive = AckermannDrive{0.3, 0.1};
  EXPECT_EQ(sim->Command("lely1", command).code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(sim->Command("nobody", TwistCommand(0.1, 0)).code(), absl::StatusCode::kNotFound);
}

}  // namespace
}  // namespace fleetnav::sim
