// Faults from the world file and at run time, and Reset.
#include <gtest/gtest.h>

#include <cmath>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/sim/simulation.hpp"
#include "fleetnav/sim/world_rasterizer.hpp"
#include "sim_test_util.hpp"

namespace fleetnav::sim {
namespace {

using testing::TwistCommand;

std::unique_ptr<Simulation> Make(const WorldDescription& world, uint64_t seed = 1) {
  SimulationParams params;
  params.seed = seed;
  absl::StatusOr<std::unique_ptr<Simulation>> sim = Simulation::Create(world, params);
  EXPECT_TRUE(sim.ok()) << sim.status();
  return sim.ok() ? std::move(*sim) : nullptr;
}

WorldDescription LoadShipped(const std::string& name) {
  absl::StatusOr<WorldDescription> world = LoadWorld(std::string(FLEETNAV_WORLDS_DIR) + "/" + name);
  EXPECT_TRUE(world.ok()) << world.status();
  return world.ok() ? *world : WorldDescription{};
}

bool Detected(const SensorFrame& frame, const std::string& name) {
  for (const InductiveSample& s : frame.inductive) {
    if (s.name == name) return s.detected;
  }
  return false;
}

const RangeReading& Range(const SensorFrame& frame, const std::string& name) {
  for (const RangeReading& r : frame.ultrasonic) {
    if (r.name == name) return r;
  }
  static const RangeReading kNone;
  ADD_FAILURE() << name;
  return kNone;
}

TEST(WorldFaultsTest, BarnErrorsIsTheBarnPlusCasesABC) {
  const WorldDescription barn = LoadShipped("barn.yaml");
  const WorldDescription errors = LoadShipped("barn_errors.yaml");
  EXPECT_EQ(errors.name, barn.name);  // one site: barn's routes and map are its own
  ASSERT_EQ(errors.boxes.size(), barn.boxes.size());
  for (size_t i = 0; i < barn.boxes.size(); ++i) {
    EXPECT_EQ(errors.boxes[i].center_m, barn.boxes[i].center_m);
    EXPECT_EQ(errors.boxes[i].size_m, barn.boxes[i].size_m);
  }
  ASSERT_EQ(errors.stripes.size(), barn.stripes.size());
  ASSERT_EQ(errors.cylinders.size(), barn.cylinders.size());
  ASSERT_EQ(errors.faults.size(), 3u);
  EXPECT_EQ(errors.faults[0].label, "A");
  EXPECT_EQ(errors.faults[0].type, FaultType::kHideUltrasonicRegion);
  EXPECT_EQ(errors.faults[1].type, FaultType::kRemoveFenceSegment);
  EXPECT_EQ(errors.faults[2].type, FaultType::kRemoveStripeSegment);
  EXPECT_TRUE(barn.faults.empty());
}

TEST(WorldFaultsTest, CaseBRemovesTwoMetresOfFenceFromSensingAndPhysics) {
  const WorldDescription barn = LoadShipped("barn.yaml");
  const WorldDescription errors = LoadShipped("barn_errors.yaml");
  // The left ultrasonic at base x + 1.57; put it at x = 3 (inside B) and at x = 6 (outside).
  auto left_at = [&](const WorldDescription& world, double sensor_x) {
    std::unique_ptr<Simulation> sim = Make(world);
    EXPECT_TRUE(sim->AddRobot("lely1", "lely-vector", Pose2(sensor_x - 1.57, 4.7, 0)).ok());
    return Range(*sim->Sense("lely1"), "ultrasonic_left");
  };
  EXPECT_TRUE(left_at(barn, 3.0).echo);
  EXPECT_FALSE(left_at(errors, 3.0).echo);
  EXPECT_TRUE(left_at(errors, 6.0).echo);
  EXPECT_NEAR(left_at(errors, 6.0).range_m, 5.85 - 4.95, 0.05);
  std::unique_ptr<Simulation> sim = Make(errors);
  // The fence box was cut into two pieces around x in [2, 4].
  int north_pieces = 0;
  for (const BoxObstacle& box : sim->current_world().boxes) {
    if (box.kind == "fence" && std::abs(box.center_m.y() - 5.9) < 1e-9) ++north_pieces;
  }
  EXPECT_EQ(north_pieces, 2);
  // The map is still drawn from the barn as built (the fence is on the map).
  EXPECT_EQ(sim->world().boxes.size(), barn.boxes.size());
}

TEST(WorldFaultsTest, CaseAHidesTheCornerAndCaseCTheArcStripe) {
  const WorldDescription barn = LoadShipped("barn.yaml");
  const WorldDescription errors = LoadShipped("barn_errors.yaml");
  // A Lely heading north-west at the corner arc with its left sensor towards it.
  // The left sensor (1.57, 0.25, +90° in base_link) 0.9 m from the arc's middle (centre
  // (-9, 6.9), radius 1, at 225°), looking at it along the radius.
  auto corner = [&](const WorldDescription& world) {
    std::unique_ptr<Simulation> sim = Make(world);
    const Eigen::Vector2d arc = Eigen::Vector2d(-9, 6.9) + Eigen::Vector2d(-M_SQRT1_2, -M_SQRT1_2);
    const Eigen::Vector2d at = arc + 0.9 * Eigen::Vector2d(-M_SQRT1_2, -M_SQRT1_2);
    const Pose2 sensor_pose(at.x(), at.y(), kPi / 4);
    const Pose2 base = sensor_pose * Pose2(1.57, 0.25, kPi / 2).Inverse();
    EXPECT_TRUE(sim->AddRobot("lely1", "lely-vector", base).ok());
    return Range(*sim->Sense("lely1"), "ultrasonic_left");
  };
  EXPECT_TRUE(corner(barn).echo);
  EXPECT_FALSE(corner(errors).echo);
  // Case C: the arc stripe 7 from (-10.5, 4.2) to (-10, 4.7); its midpoint is gone.
  const Eigen::Vector2d mid(-10.0 - 0.5 * std::cos(kPi / 4), 4.2 + 0.5 * std::sin(kPi / 4));
  auto over = [&](const WorldDescription& world, const Eigen::Vector2d& p) {
    std::unique_ptr<Simulation> sim = Make(world);
    // inductive_left at (0.485, 0.05) in base_link.
    EXPECT_TRUE(sim->AddRobot("lely1", "lely-vector", Pose2(p.x() - 0.485, p.y() - 0.05, 0)).ok());
    return Detected(*sim->Sense("lely1"), "inductive_left");
  };
  EXPECT_TRUE(over(barn, mid));
  EXPECT_FALSE(over(errors, mid));
  EXPECT_TRUE(over(errors, Eigen::Vector2d(-5.0, 4.7)));  // stripe 1 is still there
}

TEST(InjectFaultTest, ValidatesItsArguments) {
  std::unique_ptr<Simulation> sim = testing::MakeSimulation(1);
  ASSERT_TRUE(sim->AddRobot("lely1", "lely-vector", Pose2(0, 0, 0)).ok());
  FaultSpec empty_region;
  empty_region.type = FaultType::kHideUltrasonicRegion;
  EXPECT_EQ(sim->InjectFault(empty_region).code(), absl::StatusCode::kInvalidArgument);
  FaultSpec unknown_robot;
  unknown_robot.type = FaultType::kSlowDown;
  unknown_robot.robot_id = "ghost";
  unknown_robot.factor = 0.5;
  EXPECT_EQ(sim->InjectFault(unknown_robot).code(), absl::StatusCode::kNotFound);
  FaultSpec unknown_sensor;
  unknown_sensor.type = FaultType::kSensorDropout;
  unknown_sensor.robot_id = "lely1";
  unknown_sensor.sensor_name = "radar";
  EXPECT_EQ(sim->InjectFault(unknown_sensor).code(), absl::StatusCode::kNotFound);
  FaultSpec bad_factor;
  bad_factor.type = FaultType::kWheelSlipRegion;
  bad_factor.region_max_m = Eigen::Vector2d(1, 1);
  bad_factor.factor = 1.5;
  EXPECT_EQ(sim->InjectFault(bad_factor).code(), absl::StatusCode::kInvalidArgument);
  FaultSpec negative;
  negative.type = FaultType::kSlowDown;
  negative.robot_id = "lely1";
  negative.duration_s = -1;
  EXPECT_EQ(sim->InjectFault(negative).code(), absl::StatusCode::kInvalidArgument);
  EXPECT_TRUE(sim->active_faults().empty());
}

TEST(InjectFaultTest, DropoutLastsItsPeriodAndSlowDownSlows) {
  const WorldDescription barn = LoadShipped("barn.yaml");
  std::unique_ptr<Simulation> sim = Make(barn);
  ASSERT_TRUE(sim->AddRobot("on_stripe", "lely-vector", Pose2(-0.485, 4.65, 0)).ok());
  ASSERT_TRUE(Detected(*sim->Sense("on_stripe"), "inductive_left"));
  FaultSpec dropout;
  dropout.type = FaultType::kSensorDropout;
  dropout.robot_id = "on_stripe";
  dropout.sensor_name = "inductive_left";
  dropout.duration_s = 0.1;
  ASSERT_TRUE(sim->InjectFault(dropout).ok());
  EXPECT_FALSE(Detected(*sim->Sense("on_stripe"), "inductive_left"));
  for (int i = 0; i < 5; ++i) sim->Advance();
  EXPECT_TRUE(Detected(*sim->Sense("on_stripe"), "inductive_left"));

  std::unique_ptr<Simulation> fast = testing::MakeSimulation(1);
  std::unique_ptr<Simulation> slow = testing::MakeSimulation(1);
  for (Simulation* s : {fast.get(), slow.get()}) {
    ASSERT_TRUE(s->AddRobot("car", "ackermann-delivery", Pose2(0, 0, 0)).ok());
    ASSERT_TRUE(s->Command("car", TwistCommand(0.8, 0.0)).ok());
  }
  FaultSpec half;
  half.type = FaultType::kSlowDown;
  half.robot_id = "car";
  half.factor = 0.5;
  ASSERT_TRUE(slow->InjectFault(half).ok());
  for (int i = 0; i < 300; ++i) {
    fast->Advance();
    slow->Advance();
  }
  // The physical car's tyres creep a little under the rolling resistance of its front wheels.
  EXPECT_NEAR(fast->GroundTruth().robots[0].velocity.vx_mps, 0.8, 1e-3);
  EXPECT_NEAR(slow->GroundTruth().robots[0].velocity.vx_mps, 0.4, 1e-3);
}

TEST(InjectFaultTest, WheelSlipMakesEncodersOverCount) {
  for (const char* kind : {"lely-vector", "mecanum-platform"}) {
    std::unique_ptr<Simulation> sim = testing::MakeSimulation(4);
    ASSERT_TRUE(sim->AddRobot("r", kind, Pose2(0, 0, 0)).ok());
    FaultSpec slip;
    slip.type = FaultType::kWheelSlipRegion;
    slip.region_min_m = Eigen::Vector2d(-5, -5);
    slip.region_max_m = Eigen::Vector2d(50, 5);
    slip.factor = 0.8;
    ASSERT_TRUE(sim->InjectFault(slip).ok());
    ASSERT_TRUE(sim->Command("r", TwistCommand(0.3, 0.0)).ok());
    for (int i = 0; i < 500; ++i) sim->Advance();
    const RobotModel model = *sim->ModelOf("r");
    const SensorFrame frame = *sim->Sense("r");
    const double wheel_travel = static_cast<double>(frame.encoders[0].ticks) /
                                model.encoder_ticks_per_rev * 2 * kPi * model.wheel_radius_m;
    const double ground = sim->GroundTruth().robots[0].pose.x_m();
    EXPECT_NEAR(ground / wheel_travel, 0.8, 0.01) << kind;
  }
}

TEST(ResetTest, StartsOverBitIdenticallyAndClearsRunTimeFaults) {
  const WorldDescription yard = LoadShipped("delivery_yard.yaml");
  std::unique_ptr<Simulation> sim = Make(yard, 9);
  ASSERT_TRUE(sim->AddRobot("delivery1", "ackermann-delivery", yard.robots[0].pose).ok());
  ASSERT_TRUE(sim->AddRobot("lely", "lely-vector", Pose2(-10, -10, 0)).ok());
  auto run = [&] {
    std::vector<SensorFrame> frames;
    for (int i = 0; i < 60; ++i) {
      for (const std::string& id : sim->robot_ids()) {
        frames.push_back(*sim->Sense(id));
        EXPECT_TRUE(sim->Command(id, TwistCommand(0.4, 0.1)).ok());
      }
      sim->Advance();
    }
    return frames;
  };
  const std::vector<SensorFrame> first = run();
  const Pose2 end = sim->GroundTruth().robots[1].pose;
  FaultSpec slow;
  slow.type = FaultType::kSlowDown;
  slow.robot_id = "lely";
  slow.factor = 0.1;
  ASSERT_TRUE(sim->InjectFault(slow).ok());
  sim->Reset(9);
  EXPECT_EQ(sim->tick(), 0u);
  EXPECT_TRUE(sim->active_faults().empty());
  EXPECT_EQ(sim->robot_ids().size(), 2u);
  const std::vector<SensorFrame> second = run();
  ASSERT_EQ(first.size(), second.size());
  for (size_t i = 0; i < first.size(); ++i) {
    EXPECT_EQ(first[i].imu.gyro_z_radps, second[i].imu.gyro_z_radps);
    EXPECT_EQ(first[i].encoders[0].ticks, second[i].encoders[0].ticks);
  }
  EXPECT_EQ(sim->GroundTruth().robots[1].pose.x_m(), end.x_m());
}

}  // namespace
}  // namespace fleetnav::sim
