// Ultrasonic, inductive, laser, charger contact, bumper and GPS against known geometry.
#include "fleetnav/sim/exteroceptive_sensors.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/sim/simulation.hpp"
#include "sim_test_util.hpp"

namespace fleetnav::sim {
namespace {

const RangeReading* FindRange(const SensorFrame& frame, const std::string& name) {
  for (const RangeReading& r : frame.ultrasonic) {
    if (r.name == name) return &r;
  }
  return nullptr;
}

bool Inductive(const SensorFrame& frame, const std::string& name) {
  for (const InductiveSample& s : frame.inductive) {
    if (s.name == name) return s.detected;
  }
  ADD_FAILURE() << "no inductive sensor " << name;
  return false;
}

std::unique_ptr<Simulation> Make(const WorldDescription& world, uint64_t seed = 1) {
  SimulationParams params;
  params.seed = seed;
  absl::StatusOr<std::unique_ptr<Simulation>> sim = Simulation::Create(world, params);
  EXPECT_TRUE(sim.ok()) << sim.status();
  return sim.ok() ? std::move(*sim) : nullptr;
}

TEST(UltrasonicTest, WallAtKnownDistanceReadsWithinItsNoise) {
  // The Lely's left ultrasonic looks along +y from (x 1.57, y 0.25) in base_link.
  const RobotModel lely = LelyVectorModel();
  const SensorMount* mount = lely.FindSensor("ultrasonic_left");
  ASSERT_NE(mount, nullptr);
  const double distance = 1.2;
  WorldDescription world = testing::EmptyWorld();
  world.boxes.push_back(
      {"fence", {0.0, mount->pose_in_base.y_m() + distance + 0.05}, {20.0, 0.1}, 0.0, 1.2});
  std::unique_ptr<Simulation> sim = Make(world);
  ASSERT_TRUE(sim->AddRobot("lely1", "lely-vector", Pose2(0, 0, 0)).ok());
  const UltrasonicParams params;
  int echoes = 0;
  double sum = 0.0;
  const int samples = 400;
  for (int i = 0; i < samples; ++i) {
    absl::StatusOr<SensorFrame> frame = sim->Sense("lely1");
    ASSERT_TRUE(frame.ok());
    const RangeReading* left = FindRange(*frame, "ultrasonic_left");
    ASSERT_NE(left, nullptr);
    if (!left->echo) continue;  // dropout
    ++echoes;
    sum += left->range_m;
    EXPECT_NEAR(left->range_m, distance, 5 * params.noise_stddev_m);
    const RangeReading* right = FindRange(*frame, "ultrasonic_right");
    ASSERT_NE(right, nullptr);
    EXPECT_FALSE(right->echo);  // nothing within 2.5 m on the right
    EXPECT_DOUBLE_EQ(right->range_m, params.max_range_m);
  }
  EXPECT_GT(echoes, samples * 0.95);
  EXPECT_NEAR(sum / echoes, distance, 0.005);
}

TEST(UltrasonicTest, ObliqueWallsGiveNoEchoAndLowObstaclesAreNotSeen) {
  WorldDescription world = testing::EmptyWorld();
  // A wall at 60° to the beam (incidence beyond 40°).
  world.boxes.push_back({"wall", {1.57, 1.5}, {6.0, 0.1}, 60.0 * kDegToRad, 2.0});
  // A kerb on the right, below the sensor's 0.6 m.
  world.boxes.push_back({"kerb", {1.57, -1.2}, {6.0, 0.1}, 0.0, 0.3});
  std::unique_ptr<Simulation> sim = Make(world);
  ASSERT_TRUE(sim->AddRobot("lely1", "lely-vector", Pose2(0, 0, 0)).ok());
  absl::StatusOr<SensorFrame> frame = sim->Sense("lely1");
  ASSERT_TRUE(frame.ok());
  EXPECT_FALSE(FindRange(*frame, "ultrasonic_left")->echo);
  EXPECT_FALSE(FindRange(*frame, "ultrasonic_right")->echo);
}

TEST(InductiveTest, FiresExactlyOverStripesAndNeverElsewhere) {
  const RobotModel lely = LelyVectorModel();
  const SensorMount* left = lely.FindSensor("inductive_left");
  ASSERT_NE(left, nullptr);
  WorldDescription world = testing::EmptyWorld();
  world.stripes.push_back({1, {{-10, 0.0}, {10, 0.0}}, 0.05});
  // Slide the robot sideways across the stripe (kinematically placed via fresh simulations).
  for (double offset = -0.3; offset <= 0.3; offset += 0.005) {
    std::unique_ptr<Simulation> sim = Make(world);
    ASSERT_TRUE(sim->AddRobot("lely1", "lely-vector", Pose2(0, -offset, 0)).ok());
    absl::StatusOr<SensorFrame> frame = sim->Sense("lely1");
    ASSERT_TRUE(frame.ok());
    const double left_y = -offset + left->pose_in_base.y_m();
    const double right_y = -offset - left->pose_in_base.y_m();
    EXPECT_EQ(Inductive(*frame, "inductive_left"), std::abs(left_y) <= 0.025) << offset;
    EXPECT_EQ(Inductive(*frame, "inductive_right"), std::abs(right_y) <= 0.025) << offset;
  }
}

TEST(LaserTest, SeesTrolleyLegsWallsAndOtherRobots) {
  WorldDescription world = testing::EmptyWorld();
  world.boxes.push_back({"wall", {5.0, 0.0}, {0.2, 20.0}, 0.0, 2.0});
  // A trolley (a body: the laser sees its legs where they stand) with a leg at (2, 1).
  Trolley trolley;
  trolley.id = "t";
  trolley.center_m = Eigen::Vector2d(2.5, 1.3);
  trolley.size_m = Eigen::Vector2d(1.04, 0.64);
  trolley.leg_radius_m = 0.02;
  world.trolleys.push_back(trolley);
  std::unique_ptr<Simulation> sim = Make(world);
  ASSERT_TRUE(sim->AddRobot("omni", "mecanum-platform", Pose2(0, 0, 0)).ok());
  ASSERT_TRUE(sim->AddRobot("car", "ackermann-delivery", Pose2(0, -3, kPi / 2)).ok());
  absl::StatusOr<SensorFrame> frame = sim->Sense("omni");  // tick 0 is a laser tick
  ASSERT_TRUE(frame.ok());
  ASSERT_EQ(frame->lasers.size(), 1u);
  const LaserScanSample& scan = frame->lasers[0];
  ASSERT_EQ(scan.ranges_m.size(), 541u);
  const double laser_x = 0.35;
  auto range_at = [&](double angle) {
    const int i =
        static_cast<int>(std::lround((angle - scan.angle_min_rad) / scan.angle_increment_rad));
    return static_cast<double>(scan.ranges_m[static_cast<size_t>(i)]);
  };
  // Straight ahead: the wall's face at x = 4.9.
  EXPECT_NEAR(range_at(0.0), 4.9 - laser_x, 0.05);
  // Towards the leg at (2, 1).
  const double leg_angle = std::atan2(1.0, 2.0 - laser_x);
  const double leg_distance = std::hypot(1.0, 2.0 - laser_x) - 0.02;
  double best = 1e9;
  for (double a = leg_angle - 0.02; a <= leg_angle + 0.02; a += 0.005)
    best = std::min(best, range_at(a));
  EXPECT_NEAR(best, leg_distance, 0.05);
  // Down and to the right: the Ackermann robot's body (its front at y = -3 + 0.75).
  EXPECT_LT(range_at(-kPi / 2 - 0.12), 3.0);
  // Not a laser tick: no scan.
  sim->Advance();
  EXPECT_TRUE(sim->Sense("omni")->lasers.empty());
}

TEST(ContactSensorsTest, ChargerContactBumperAndGps) {
  WorldDescription world = testing::EmptyWorld();
  // The Lely's charger contact is at its front, x = 1.395 in base_link.
  world.cylinders.push_back({"charging_pole", {1.395 + 0.15 + 0.03, 0.0}, 0.15, 1.5});
  std::unique_ptr<Simulation> sim = Make(world);
  ASSERT_TRUE(sim->AddRobot("lely1", "lely-vector", Pose2(0, 0, 0)).ok());
  ASSERT_TRUE(sim->AddRobot("car", "ackermann-delivery", Pose2(10, 10, 0)).ok());
  absl::StatusOr<SensorFrame> lely = sim->Sense("lely1");
  ASSERT_TRUE(lely.ok());
  EXPECT_TRUE(lely->charger_contact);
  EXPECT_FALSE(lely->bumper);  // 3 cm away: beyond the bumper's 2 cm
  absl::StatusOr<SensorFrame> car = sim->Sense("car");
  ASSERT_TRUE(car.ok());
  ASSERT_TRUE(car->gps.has_value());
  EXPECT_NEAR(car->gps->x_m, 10.3, 5 * 0.3);
  EXPECT_NEAR(car->gps->y_m, 10.0, 5 * 0.3);
  EXPECT_FALSE(car->charger_contact);
  // A second robot touching the first sets both bumpers.
  ASSERT_TRUE(sim->AddRobot("omni", "mecanum-platform", Pose2(0, 0.8 + 0.24 + 0.01, 0)).ok());
  EXPECT_TRUE(sim->Sense("lely1")->bumper);
  EXPECT_TRUE(sim->Sense("omni")->bumper);
}

TEST(ImuTest, AccelerometerSeesTheRamp) {
  std::unique_ptr<Simulation> sim = testing::MakeSimulation(2);
  ASSERT_TRUE(sim->AddRobot("car", "ackermann-delivery", Pose2(0, 0, 0)).ok());
  ASSERT_TRUE(sim->Command("car", testing::TwistCommand(1.0, 0.0)).ok());
  double sum = 0.0;
  for (int i = 0; i < 50; ++i) {
    sim->Advance();
    sum += sim->Sense("car")->imu.accel_x_mps2;
  }
  EXPECT_NEAR(sum / 50, AckermannDeliveryModel().limits.max_accel_mps2, 0.02);
}

}  // namespace
}  // namespace fleetnav::sim
