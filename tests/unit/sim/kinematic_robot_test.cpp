// The kinematic robots: mecanum kinematics (KUKA eq. 4.5-4.17), the kinematic omni platform
// (SimulationParams::kinematic_omni), the kinematic Ackermann bicycle
// (SimulationParams::kinematic_ackermann) with steering limits, wheel slip and slow-down.
#include "fleetnav/sim/kinematic_robot.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/sim/simulation.hpp"
#include "sim_test_util.hpp"

namespace fleetnav::sim {
namespace {

using testing::MakeSimulation;
using testing::TwistCommand;

void Ticks(Simulation& sim, int n) {
  for (int i = 0; i < n; ++i) sim.Advance();
}

Pose2 PoseOf(const Simulation& sim, const std::string& id) {
  for (const RobotTruth& robot : sim.GroundTruth().robots) {
    if (robot.robot_id == id) return robot.pose;
  }
  return Pose2();
}

TEST(MecanumKinematicsTest, ForwardOfInverseIsIdentity) {
  const RobotModel model = MecanumPlatformModel();
  NoiseStream random(7);
  for (int i = 0; i < 200; ++i) {
    const Twist2 twist{random.Gaussian(0.4), random.Gaussian(0.4), random.Gaussian(0.8)};
    const Twist2 back = MecanumForward(model, MecanumInverse(model, twist));
    EXPECT_NEAR(back.vx_mps, twist.vx_mps, 1e-12);
    EXPECT_NEAR(back.vy_mps, twist.vy_mps, 1e-12);
    EXPECT_NEAR(back.yaw_rate_radps, twist.yaw_rate_radps, 1e-12);
  }
  // Pure sideways motion: the diagonal wheel pairs turn against each other.
  const MecanumWheelRates sideways = MecanumInverse(model, Twist2{0, 0.2, 0});
  EXPECT_NEAR(sideways[0], -sideways[1], 1e-12);
  EXPECT_NEAR(sideways[0], sideways[3], 1e-12);
  EXPECT_NEAR(sideways[1], sideways[2], 1e-12);
}

SimulationParams KinematicOmni() {
  SimulationParams params;
  params.kinematic_omni = true;
  return params;
}

TEST(KinematicRobotTest, OmniDrivesSidewaysAndEncodersMatchTheMotion) {
  std::unique_ptr<Simulation> sim = MakeSimulation(3, KinematicOmni());
  ASSERT_TRUE(sim->AddRobot("omni", "mecanum-platform", Pose2(0, 0, 0)).ok());
  ActuatorCommand command;
  command.drive = Twist2{0.0, 0.3, 0.0};
  ASSERT_TRUE(sim->Command("omni", command).ok());
  Ticks(*sim, 250);  // 5 s: 0.6 s of ramp at 0.5 m/s² then 0.3 m/s
  const Pose2 pose = PoseOf(*sim, "omni");
  EXPECT_NEAR(pose.x_m(), 0.0, 1e-9);
  EXPECT_NEAR(pose.y_m(), 0.3 * 5.0 - 0.5 * 0.3 * 0.6, 0.01);
  absl::StatusOr<SensorFrame> frame = sim->Sense("omni");
  ASSERT_TRUE(frame.ok());
  ASSERT_EQ(frame->encoders.size(), 4u);
  const RobotModel model = MecanumPlatformModel();
  MecanumWheelRates revs;
  for (size_t i = 0; i < 4; ++i) {
    revs[i] = static_cast<double>(frame->encoders[i].ticks) / model.encoder_ticks_per_rev * 2 * kPi;
  }
  const Twist2 travelled = MecanumForward(model, revs);  // wheel angles -> displacement
  EXPECT_NEAR(travelled.vy_mps, pose.y_m(), 0.002);
  EXPECT_NEAR(travelled.vx_mps, 0.0, 0.002);
  EXPECT_EQ(sim->Command("omni", ActuatorCommand{0, WheelSpeeds{1, 1}}).code(),
            absl::StatusCode::kInvalidArgument);
}

TEST(KinematicRobotTest, AckermannRespectsSteeringAngleAndRateLimits) {
  SimulationParams kinematic_ackermann;
  kinematic_ackermann.kinematic_ackermann = true;
  std::unique_ptr<Simulation> sim = MakeSimulation(1, kinematic_ackermann);
  ASSERT_TRUE(sim->AddRobot("car", "ackermann-delivery", Pose2(0, 0, 0)).ok());
  ActuatorCommand command;
  command.drive = AckermannDrive{0.5, 1.2};  // beyond the 0.5 rad lock
  ASSERT_TRUE(sim->Command("car", command).ok());
  // After 0.5 s the steering (0.5 rad/s) has reached at most 0.25 rad.
  Ticks(*sim, 25);
  const RobotModel model = AckermannDeliveryModel();
  Twist2 v = sim->GroundTruth().robots[0].velocity;
  double steering = std::atan(v.yaw_rate_radps * model.wheelbase_m / v.vx_mps);
  EXPECT_NEAR(steering, 0.25, 0.011);
  Ticks(*sim, 200);
  v = sim->GroundTruth().robots[0].velocity;
  steering = std::atan(v.yaw_rate_radps * model.wheelbase_m / v.vx_mps);
  EXPECT_NEAR(steering, 0.5, 1e-9);
  EXPECT_NEAR(v.vx_mps, 0.5, 1e-9);
  EXPECT_NEAR(v.vy_mps, 0.0, 1e-12);
  // The turning circle of radius L / tan(0.5).
  EXPECT_NEAR(v.vx_mps / v.yaw_rate_radps, model.wheelbase_m / std::tan(0.5), 1e-9);
  EXPECT_EQ(sim->Command("car", ActuatorCommand{0, WheelSpeeds{1, 1}}).code(),
            absl::StatusCode::kInvalidArgument);
  ASSERT_TRUE(sim->Command("car", TwistCommand(0.4, 0.0)).ok());
  Ticks(*sim, 100);
  EXPECT_NEAR(sim->GroundTruth().robots[0].velocity.yaw_rate_radps, 0.0, 1e-9);
}

TEST(KinematicRobotTest, StopsAtObstaclesAndReportsTheContact) {
  WorldDescription world = testing::EmptyWorld();
  world.boxes.push_back({"wall", {3.0, 0.0}, {0.2, 4.0}, 0.0, 2.0});
  absl::StatusOr<std::unique_ptr<Simulation>> sim = Simulation::Create(world, KinematicOmni());
  ASSERT_TRUE(sim.ok());
  ASSERT_TRUE((*sim)->AddRobot("omni", "mecanum-platform", Pose2(0, 0, 0)).ok());
  ASSERT_TRUE((*sim)->Command("omni", TwistCommand(0.5, 0.0)).ok());
  Ticks(**sim, 500);
  const GroundTruthSnapshot truth = (*sim)->GroundTruth();
  EXPECT_LT(truth.robots[0].pose.x_m() + 0.394, 2.9);
  EXPECT_GT(truth.robots[0].pose.x_m() + 0.394, 2.85);
  ASSERT_FALSE(truth.contacts.empty());
  EXPECT_EQ(truth.contacts.back().other, "static");
  EXPECT_TRUE((*sim)->Sense("omni")->bumper);
}

}  // namespace
}  // namespace fleetnav::sim
