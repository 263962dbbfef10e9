// Trolleys are bodies: the ground truth lists where they stand, a physical robot that drives
// into a leg pushes the trolley along (the contact named after the trolley), a kinematic robot
// stops at it, and Reset puts them back.
#include "fleetnav/sim/trolley_body.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/sim/simulation.hpp"
#include "sim_test_util.hpp"

namespace fleetnav::sim {
namespace {

/// An empty floor with one 0.9 × 0.55 m trolley "t1" at (x, y), yaw 0, standing 0.3 m left of
/// the x axis so that a platform driving along it meets its right legs.
std::unique_ptr<Simulation> TrolleyFloor(SimulationParams params = {}) {
  WorldDescription world = testing::EmptyWorld();
  Trolley trolley;
  trolley.id = "t1";
  trolley.center_m = Eigen::Vector2d(1.5, 0.3);
  trolley.size_m = Eigen::Vector2d(0.9, 0.55);
  trolley.leg_radius_m = 0.02;
  world.trolleys.push_back(trolley);
  absl::StatusOr<std::unique_ptr<Simulation>> sim = Simulation::Create(world, params);
  EXPECT_TRUE(sim.ok()) << sim.status();
  return sim.ok() ? std::move(*sim) : nullptr;
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

}  // namespace
}  // namespace fleetnav::sim
