// Trolleys are bodies: the ground truth lists where they stand, a physical robot that drives
// into a leg pushes the trolley along (the contact named after the trolley), a kinematic robot
// stops at it, and Reset puts them back.
#include "fleetnav/sim/trolley_body.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/sim/simulation.hpp"
#include "sim_test_util.hpp"

namespace fleetnav::sim {
namespace {

/// An empty floor with trolleys of `size_m` at `centers`, yaw 0, named t1, t2, … .
std::unique_ptr<Simulation> TrolleysOnFloor(const std::vector<Eigen::Vector2d>& centers,
                                            const Eigen::Vector2d& size_m, double leg_radius_m,
                                            SimulationParams params) {
  WorldDescription world = testing::EmptyWorld();
  for (size_t i = 0; i < centers.size(); ++i) {
    Trolley trolley;
    trolley.id = absl::StrCat("t", i + 1);
    trolley.center_m = centers[i];
    trolley.size_m = size_m;
    trolley.leg_radius_m = leg_radius_m;
    world.trolleys.push_back(trolley);
  }
  absl::StatusOr<std::unique_ptr<Simulation>> sim = Simulation::Create(world, params);
  EXPECT_TRUE(sim.ok()) << sim.status();
  return sim.ok() ? std::move(*sim) : nullptr;
}

/// One 0.9 × 0.55 m trolley "t1" standing 0.3 m left of the x axis, so that a platform driving
/// along it meets its right legs.
std::unique_ptr<Simulation> TrolleyFloor(SimulationParams params = {}) {
  return TrolleysOnFloor({{1.5, 0.3}}, {0.9, 0.55}, 0.02, params);
}

TrolleyTruth TrolleyOf(const Simulation& sim) { return sim.GroundTruth().trolleys.at(0); }

void DriveForward(Simulation& sim, double speed_mps, int ticks) {
  ActuatorCommand command;
  command.drive = Twist2{speed_mps, 0.0, 0.0};
  ASSERT_TRUE(sim.Command("omni", command).ok());
  for (int i = 0; i < ticks; ++i) sim.Advance();
}

TEST(TrolleyBodyTest, TheGroundTruthListsWhereEachTrolleyStands) {
  std::unique_ptr<Simulation> sim = TrolleyFloor();
  for (int i = 0; i < 100; ++i) sim->Advance();
  ASSERT_EQ(sim->GroundTruth().trolleys.size(), 1U);
  const TrolleyTruth t = TrolleyOf(*sim);
  EXPECT_EQ(t.trolley_id, "t1");
  EXPECT_TRUE(t.pose.IsNear(Pose2(1.5, 0.3, 0.0), 0.002, 0.005)) << t.pose.DebugString();
  EXPECT_EQ(t.carrier_robot_id, "");
}

TEST(TrolleyBodyTest, APhysicalPlatformPushesATrolleyItDrivesInto) {
  std::unique_ptr<Simulation> sim = TrolleyFloor();
  ASSERT_TRUE(sim->AddRobot("omni", "mecanum-platform", Pose2(0, 0, 0)).ok());
  DriveForward(*sim, 0.3, 300);  // 6 s: about 1.6 m, into the leg at (1.07, 0.05)
  const TrolleyTruth t = TrolleyOf(*sim);
  EXPECT_GT(t.pose.x_m() - 1.5, 0.3) << t.pose.DebugString();
  const GroundTruthSnapshot truth = sim->GroundTruth();
  bool named = false;
  for (const SimContact& c : truth.contacts) named |= c.robot_id == "omni" && c.other == "t1";
  EXPECT_TRUE(named);
  EXPECT_GE(truth.robots[0].collisions_world, 1);
  EXPECT_EQ(truth.robots[0].collisions_robots, 0);

  // Reset puts the trolley back where the world file has it.
  sim->Reset(1);
  EXPECT_TRUE(TrolleyOf(*sim).pose.IsNear(Pose2(1.5, 0.3, 0.0), 1e-9, 1e-9));
}

TEST(TrolleyBodyTest, AKinematicPlatformStopsAtATrolleyLeg) {
  SimulationParams params;
  params.kinematic_omni = true;
  std::unique_ptr<Simulation> sim = TrolleyFloor(params);
  ASSERT_TRUE(sim->AddRobot("omni", "mecanum-platform", Pose2(0, 0, 0)).ok());
  DriveForward(*sim, 0.3, 300);
  EXPECT_TRUE(TrolleyOf(*sim).pose.IsNear(Pose2(1.5, 0.3, 0.0), 0.005, 0.01));
  const GroundTruthSnapshot truth = sim->GroundTruth();
  ASSERT_FALSE(truth.contacts.empty());
  EXPECT_EQ(truth.contacts.back().other, "t1");
  EXPECT_LT(truth.robots[0].pose.x_m(), 1.0);
}

/// Store trolleys of 1.0 × 0.7 m (the platform fits between their legs) at `centers`.
std::unique_ptr<Simulation> StoreTrolleys(const std::vector<Eigen::Vector2d>& centers,
                                          SimulationParams params = {}) {
  return TrolleysOnFloor(centers, {1.0, 0.7}, 0.025, params);
}

absl::Status Drive(Simulation& sim, const Twist2& twist, bool lift_raised, int ticks) {
  ActuatorCommand command;
  command.drive = twist;
  command.lift_raised = lift_raised;
  if (absl::Status s = sim.Command("omni", command); !s.ok()) return s;
  for (int i = 0; i < ticks; ++i) sim.Advance();
  return absl::OkStatus();
}

class LiftTest : public ::testing::TestWithParam<bool> {};  // kinematic_omni

TEST_P(LiftTest, ARaisedLiftCarriesTheTrolleyAndALoweredOneLeavesItStanding) {
  SimulationParams params;
  params.kinematic_omni = GetParam();
  std::unique_ptr<Simulation> sim = StoreTrolleys({{1.5, 0.3}}, params);
  ASSERT_TRUE(sim->AddRobot("omni", "mecanum-platform", Pose2(1.51, 0.29, 0.03)).ok());
  ASSERT_TRUE(Drive(*sim, Twist2{}, true, 10).ok());
  EXPECT_EQ(TrolleyOf(*sim).carrier_robot_id, "omni");
  EXPECT_TRUE(sim->Sense("omni")->lift_loaded);

  // Carried 1 m forward and 0.5 m aside: the trolley goes with the robot, touching nothing.
  ASSERT_TRUE(Drive(*sim, Twist2{0.2, 0.0, 0.0}, true, 250).ok());
  ASSERT_TRUE(Drive(*sim, Twist2{0.0, 0.2, 0.0}, true, 125).ok());
  ASSERT_TRUE(Drive(*sim, Twist2{}, true, 50).ok());
  GroundTruthSnapshot truth = sim->GroundTruth();
  const Pose2 robot = truth.robots[0].pose;
  EXPECT_GT(robot.x_m(), 2.3) << robot.DebugString();
  const TrolleyTruth carried = TrolleyOf(*sim);
  EXPECT_LT((carried.pose.translation() - robot.translation()).norm(), 0.02)
      << carried.pose.DebugString() << " vs " << robot.DebugString();
  EXPECT_EQ(truth.robots[0].collisions(), 0);

  // Lowered: it stands where it was set down while the robot drives out backwards.
  ASSERT_TRUE(Drive(*sim, Twist2{}, false, 10).ok());
  EXPECT_EQ(TrolleyOf(*sim).carrier_robot_id, "");
  EXPECT_FALSE(sim->Sense("omni")->lift_loaded);
  const Pose2 set_down = TrolleyOf(*sim).pose;
  ASSERT_TRUE(Drive(*sim, Twist2{-0.2, 0.0, 0.0}, false, 400).ok());
  truth = sim->GroundTruth();
  EXPECT_LT(truth.robots[0].pose.x_m(), robot.x_m() - 1.2);
  EXPECT_TRUE(TrolleyOf(*sim).pose.IsNear(set_down, 0.005, 0.01))
      << TrolleyOf(*sim).pose.DebugString() << " vs " << set_down.DebugString();
  EXPECT_EQ(truth.robots[0].collisions(), 0);
}

TEST_P(LiftTest, WhatTheCarriedTrolleyTouchesCountsAsTheCarriers) {
  SimulationParams params;
  params.kinematic_omni = GetParam();
  // t2 stands 1.3 m ahead of t1: carrying t1 forward, its front legs meet t2's rear legs long
  // before the robot's own chassis could.
  std::unique_ptr<Simulation> sim = StoreTrolleys({{1.5, 0.3}, {2.8, 0.3}}, params);
  ASSERT_TRUE(sim->AddRobot("omni", "mecanum-platform", Pose2(1.5, 0.3, 0.0)).ok());
  ASSERT_TRUE(Drive(*sim, Twist2{0.2, 0.0, 0.0}, true, 150).ok());
  const GroundTruthSnapshot truth = sim->GroundTruth();
  bool named = false;
  for (const SimContact& c : truth.contacts) named |= c.robot_id == "omni" && c.other == "t2";
  EXPECT_TRUE(named);
  EXPECT_GE(truth.robots[0].collisions_world, 1);
  EXPECT_EQ(truth.trolleys[0].carrier_robot_id, "omni");
  EXPECT_EQ(truth.trolleys[1].carrier_robot_id, "");
}

INSTANTIATE_TEST_SUITE_P(PhysicalAndKinematic, LiftTest, ::testing::Bool());

TEST(TrolleyBodyTest, ALiftRaisedAwayFromATrolleyCarriesNothing) {
  std::unique_ptr<Simulation> sim = StoreTrolleys({{1.5, 0.3}});
  // Beside the trolley's centre by 0.1 m: not under its lift point.
  ASSERT_TRUE(sim->AddRobot("omni", "mecanum-platform", Pose2(1.5, 0.2, 0.0)).ok());
  ASSERT_TRUE(Drive(*sim, Twist2{}, true, 20).ok());
  EXPECT_EQ(TrolleyOf(*sim).carrier_robot_id, "");
  EXPECT_FALSE(sim->Sense("omni")->lift_loaded);
}

TEST(TrolleyBodyTest, ARobotWithoutALiftCannotRaiseOne) {
  std::unique_ptr<Simulation> sim = StoreTrolleys({});
  ASSERT_TRUE(sim->AddRobot("lely", "lely-vector", Pose2(0, 0, 0)).ok());
  ActuatorCommand command;
  command.drive = WheelSpeeds{};
  command.lift_raised = true;
  const absl::Status status = sim->Command("lely", command);
  EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(status.message().find("has no lift"), std::string::npos) << status;
}

}  // namespace
}  // namespace fleetnav::sim
