// The physical mecanum platform (KUKA thesis ch. 4, 9): mecanum wheels gripping along their
// rollers move it in any direction, the encoders read what the wheels turned, the casters
// trail the motion and swing round when it reverses, and the platform collides like any body.
#include "fleetnav/sim/mecanum_robot.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/sim/simulation.hpp"
#include "sim_test_util.hpp"

namespace fleetnav::sim {
namespace {

using testing::MakeSimulation;

constexpr double kTickS = 0.02;

void Drive(Simulation& sim, double vx_mps, double vy_mps, double seconds) {
  ActuatorCommand command;
  command.drive = Twist2{vx_mps, vy_mps, 0.0};
  ASSERT_TRUE(sim.Command("omni", command).ok());
  for (int i = 0; i < static_cast<int>(std::lround(seconds / kTickS)); ++i) sim.Advance();
}

Pose2 Truth(const Simulation& sim) { return sim.GroundTruth().robots.at(0).pose; }

/// The displacement the encoders report since the start (forward kinematics of the wheel
/// angles; exact for motion without rotation).
Eigen::Vector2d EncoderTravel(Simulation& sim) {
  const RobotModel model = MecanumPlatformModel();
  absl::StatusOr<SensorFrame> frame = sim.Sense("omni");
  EXPECT_TRUE(frame.ok());
  MecanumWheelRates angles{};
  for (size_t i = 0; i < 4; ++i) {
    angles[i] =
        static_cast<double>(frame->encoders[i].ticks) / model.encoder_ticks_per_rev * 2 * kPi;
  }
  const Twist2 travel = MecanumForward(model, angles);
  return {travel.vx_mps, travel.vy_mps};
}

TEST(MecanumRobotTest, DrivesSidewaysAndForwardAndTheEncodersAgree) {
  for (const Eigen::Vector2d& direction :
       {Eigen::Vector2d(0, 1), Eigen::Vector2d(1, 0), Eigen::Vector2d(M_SQRT1_2, -M_SQRT1_2)}) {
    std::unique_ptr<Simulation> sim = MakeSimulation(3);
    ASSERT_TRUE(sim->AddRobot("omni", "mecanum-platform", Pose2(1, 2, 0.3)).ok());
    Drive(*sim, 0.0, 0.0, 1.0);  // settle on the suspension
    const Pose2 settled = Truth(*sim);
    EXPECT_NEAR((settled.translation() - Eigen::Vector2d(1, 2)).norm(), 0.0, 0.005);
    Drive(*sim, 0.3 * direction.x(), 0.3 * direction.y(), 4.0);
    Drive(*sim, 0.0, 0.0, 1.5);
    const Pose2 end = Truth(*sim);
    const Eigen::Vector2d moved = settled.Inverse().TransformPoint(end.translation());
    // 4 s at 0.3 m/s with 0.6 s ramps at 0.5 m/s²: about 1.2 m along the command.
    EXPECT_NEAR(moved.dot(direction), 1.2, 0.06) << direction.transpose();
    EXPECT_LT(std::abs(moved.dot(Eigen::Vector2d(-direction.y(), direction.x()))), 0.03)
        << direction.transpose();
    EXPECT_NEAR(std::remainder(end.yaw_rad() - settled.yaw_rad(), 2 * kPi), 0.0, 0.02);
    // Without reversals the rollers creep little: the encoders know where the platform went
    // within 2.5 %.
    EXPECT_LT((EncoderTravel(*sim) - moved).norm(), 0.03) << direction.transpose();
    EXPECT_GT(sim->GroundTruth().robots[0].up_z, 0.999);
  }
}

TEST(MecanumRobotTest, CastersTrailTheMotionAndSwingRoundWhenItReverses) {
  std::unique_ptr<Simulation> sim = MakeSimulation(1);
  ASSERT_TRUE(sim->AddRobot("omni", "mecanum-platform", Pose2(0, 0, 0)).ok());
  const auto& body = dynamic_cast<const MecanumRobot&>(*sim->BodyOf("omni"));
  Drive(*sim, 0.0, 0.2, 2.0);  // to the left: each caster's axis leads its contact
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(body.caster_angle_rad(i), (kPi / 2), 0.1) << i;
  Drive(*sim, 0.0, 0.0, 1.0);
  Drive(*sim, 0.0, -0.2, 4.0);
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(body.caster_angle_rad(i), -(kPi / 2), 0.1) << i;
    EXPECT_NEAR(std::abs(body.caster_swivel_turned_rad(i) - (kPi / 2)), kPi, 0.1) << i;
  }
}

/// How far (metres, and radians of yaw) the platform strays off a 0.4 m move to the right that
/// follows a 0.4 m move to the `before` side and a stop.
std::pair<double, double> StrayOfSecondMove(uint64_t seed, double before_vy_mps) {
  std::unique_ptr<Simulation> sim = MakeSimulation(seed);
  EXPECT_TRUE(sim->AddRobot("omni", "mecanum-platform", Pose2(0, 0, 0)).ok());
  Drive(*sim, 0.0, before_vy_mps, 2.0);
  Drive(*sim, 0.0, 0.0, 1.0);
  const Pose2 before = Truth(*sim);
  Drive(*sim, 0.0, -0.2, 2.0);
  Drive(*sim, 0.0, 0.0, 1.0);
  const Pose2 after = Truth(*sim);
  return {std::abs(after.x_m() - before.x_m()),
          std::abs(std::remainder(after.yaw_rad() - before.yaw_rad(), 2 * kPi))};
}

TEST(MecanumRobotTest, AReversalPushesThePlatformAsideWhileTheCastersSwingRound) {
  // The casters' pull makes the rollers creep: a move after a reversal strays off its line by
  // more than one that continues the last, but by millimetres, not centimetres.
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    const double same_m = StrayOfSecondMove(seed, -0.2).first;
    const double reversed_m = StrayOfSecondMove(seed, 0.2).first;
    EXPECT_GT(reversed_m, 1.4 * same_m) << "seed " << seed;
    EXPECT_LT(reversed_m, 0.02) << "seed " << seed;
  }
}

TEST(MecanumRobotTest, StopsAtAWallAndReportsTheContact) {
  WorldDescription world = testing::EmptyWorld();
  world.boxes.push_back({"wall", {3.0, 0.0}, {0.2, 4.0}, 0.0, 2.0});
  absl::StatusOr<std::unique_ptr<Simulation>> sim = Simulation::Create(world, SimulationParams{});
  ASSERT_TRUE(sim.ok());
  ASSERT_TRUE((*sim)->AddRobot("omni", "mecanum-platform", Pose2(0, 0, 0)).ok());
  ActuatorCommand command;
  command.drive = Twist2{0.5, 0.0, 0.0};
  ASSERT_TRUE((*sim)->Command("omni", command).ok());
  for (int i = 0; i < 500; ++i) (*sim)->Advance();
  const GroundTruthSnapshot truth = (*sim)->GroundTruth();
  EXPECT_LT(truth.robots[0].pose.x_m() + 0.394, 2.91);
  EXPECT_GT(truth.robots[0].pose.x_m() + 0.394, 2.8);
  ASSERT_FALSE(truth.contacts.empty());
  EXPECT_EQ(truth.contacts.back().other, "static");
  EXPECT_EQ((*sim)->Command("omni", ActuatorCommand{0, WheelSpeeds{1, 1}}).code(),
            absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace fleetnav::sim
