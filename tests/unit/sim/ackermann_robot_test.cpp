// The physical Ackermann robot: it drives straight and its rear encoders agree, it turns on the
// circle its steering lock allows because the front tyres push it round, the steering follows
// its command at the rate limit, the front wheels take the Ackermann angles, and it stops at a
// wall with the contact reported.
#include "fleetnav/sim/ackermann_robot.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/sim/ackermann_steering.hpp"
#include "fleetnav/sim/simulation.hpp"
#include "sim_test_util.hpp"

namespace fleetnav::sim {
namespace {

using testing::MakeSimulation;

constexpr double kTickS = 0.02;

void Drive(Simulation& sim, double speed_mps, double steering_rad, double seconds) {
  ActuatorCommand command;
  command.drive = AckermannDrive{speed_mps, steering_rad};
  ASSERT_TRUE(sim.Command("car", command).ok());
  for (int i = 0; i < static_cast<int>(std::lround(seconds / kTickS)); ++i) sim.Advance();
}

Pose2 Truth(const Simulation& sim) { return sim.GroundTruth().robots.at(0).pose; }

TEST(AckermannRobotTest, DrivesStraightAndTheRearEncodersAgree) {
  std::unique_ptr<Simulation> sim = MakeSimulation(2);
  ASSERT_TRUE(sim->AddRobot("car", "ackermann-delivery", Pose2(1, 2, 0.4)).ok());
  ASSERT_TRUE(sim->BodyOf("car")->physical());
  Drive(*sim, 0.0, 0.0, 1.0);  // settle on the suspension
  const Pose2 settled = Truth(*sim);
  EXPECT_LT((settled.translation() - Eigen::Vector2d(1, 2)).norm(), 0.005);
  Drive(*sim, 0.5, 0.0, 4.0);
  Drive(*sim, 0.0, 0.0, 2.0);
  const Pose2 end = Truth(*sim);
  const Eigen::Vector2d moved = settled.Inverse().TransformPoint(end.translation());
  // 4 s at 0.5 m/s after a 1 s ramp at 0.5 m/s² (1.75 m), and 0.25 m braking: 2 m.
  EXPECT_NEAR(moved.x(), 2.0, 0.05);
  EXPECT_LT(std::abs(moved.y()), 0.02);
  EXPECT_NEAR(std::remainder(end.yaw_rad() - settled.yaw_rad(), 2 * kPi), 0.0, 0.01);
  const RobotModel model = AckermannDeliveryModel();
  absl::StatusOr<SensorFrame> frame = sim->Sense("car");
  ASSERT_TRUE(frame.ok());
  ASSERT_EQ(frame->encoders.size(), 2U);
  for (const EncoderReading& e : frame->encoders) {
    const double rolled_m =
        static_cast<double>(e.ticks) / model.encoder_ticks_per_rev * 2 * kPi * model.wheel_radius_m;
    EXPECT_NEAR(rolled_m, moved.x(), 0.02 * moved.x()) << e.name;
  }
  EXPECT_GT(sim->GroundTruth().robots[0].up_z, 0.999);
}

TEST(AckermannRobotTest, TurnsOnTheCircleOfItsSteeringLock) {
  std::unique_ptr<Simulation> sim = MakeSimulation(3);
  ASSERT_TRUE(sim->AddRobot("car", "ackermann-delivery", Pose2(0, 0, 0)).ok());
  const auto& body = dynamic_cast<const AckermannRobot&>(*sim->BodyOf("car"));
  const RobotModel model = AckermannDeliveryModel();
  // Asked for more than the lock: the steering turns at its rate limit and stops at the lock.
  Drive(*sim, 0.3, 1.2, 0.5);
  EXPECT_NEAR(*body.SteeringAngleRad(), 0.5 * model.limits.max_steering_rate_radps, 0.011);
  Drive(*sim, 0.3, 1.2, 3.0);
  EXPECT_NEAR(*body.SteeringAngleRad(), model.limits.max_steering_rad, 1e-9);
  // The steering encoder reports the angle, to its 12-bit resolution; a Lely has none.
  absl::StatusOr<SensorFrame> frame = sim->Sense("car");
  ASSERT_TRUE(frame.ok()) << frame.status();
  ASSERT_TRUE(frame->steering_angle_rad.has_value());
  EXPECT_NEAR(*frame->steering_angle_rad, model.limits.max_steering_rad, kPi / 4096.0);
  // Round the circle: the rear axle's middle keeps L / tan(δ) from the centre.
  const double radius_m = model.wheelbase_m / std::tan(model.limits.max_steering_rad);
  const Twist2 v = sim->GroundTruth().robots[0].velocity;
  EXPECT_NEAR(v.vx_mps / v.yaw_rate_radps, radius_m, 0.05 * radius_m);
  EXPECT_LT(std::abs(v.vy_mps), 0.01) << "the rear tyres hardly slide";
  double min_r = 1e9;
  double max_r = 0.0;
  Pose2 last = Truth(*sim);
  const Eigen::Vector2d centre =
      last.TransformPoint(Eigen::Vector2d(0.0, v.vx_mps / v.yaw_rate_radps));
  for (int i = 0; i < 200; ++i) {
    Drive(*sim, 0.3, 1.2, kTickS);
    last = Truth(*sim);
    const double r = (last.translation() - centre).norm();
    min_r = std::min(min_r, r);
    max_r = std::max(max_r, r);
  }
  EXPECT_NEAR(min_r, radius_m, 0.06 * radius_m);
  EXPECT_NEAR(max_r, radius_m, 0.06 * radius_m);
}

TEST(AckermannRobotTest, FrontWheelsTakeTheAckermannAngles) {
  const RobotModel model = AckermannDeliveryModel();
  const FrontWheelAngles left_turn =
      AckermannFrontWheelAngles(0.4, model.wheelbase_m, model.track_m);
  // Both front axles point at the turning centre on the rear axle's line.
  const double radius_m = model.wheelbase_m / std::tan(0.4);
  EXPECT_NEAR(std::tan(left_turn.left_rad), model.wheelbase_m / (radius_m - 0.5 * model.track_m),
              1e-9);
  EXPECT_NEAR(std::tan(left_turn.right_rad), model.wheelbase_m / (radius_m + 0.5 * model.track_m),
              1e-9);
  EXPECT_GT(left_turn.left_rad, left_turn.right_rad) << "the inner wheel turns further";
  const FrontWheelAngles right_turn =
      AckermannFrontWheelAngles(-0.4, model.wheelbase_m, model.track_m);
  EXPECT_NEAR(right_turn.right_rad, -left_turn.left_rad, 1e-9);
  const FrontWheelAngles straight = AckermannFrontWheelAngles(0.0, 1.0, 0.5);
  EXPECT_EQ(straight.left_rad, 0.0);
  EXPECT_EQ(straight.right_rad, 0.0);
}

TEST(AckermannRobotTest, StopsAtAWallAndReportsTheContact) {
  WorldDescription world = testing::EmptyWorld();
  world.boxes.push_back({"wall", {3.0, 0.0}, {0.2, 4.0}, 0.0, 2.0});
  absl::StatusOr<std::unique_ptr<Simulation>> sim = Simulation::Create(world, SimulationParams{});
  ASSERT_TRUE(sim.ok());
  ASSERT_TRUE((*sim)->AddRobot("car", "ackermann-delivery", Pose2(0, 0, 0)).ok());
  Drive(**sim, 0.5, 0.0, 10.0);
  const GroundTruthSnapshot truth = (*sim)->GroundTruth();
  const double nose_x = truth.robots[0].pose.x_m() + 0.75;  // the footprint's front
  EXPECT_LT(nose_x, 2.91);
  EXPECT_GT(nose_x, 2.8);
  ASSERT_FALSE(truth.contacts.empty());
  EXPECT_EQ(truth.contacts.back().other, "static");
  EXPECT_EQ((*sim)->Command("car", ActuatorCommand{0, WheelSpeeds{1, 1}}).code(),
            absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace fleetnav::sim
