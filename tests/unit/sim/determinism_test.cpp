// Same seed and binary -> bit-identical trajectories and sensor readings, for a mixed fleet;
// one noise stream per robot and sensor, so adding a robot leaves the others' readings alone.
#include <gtest/gtest.h>

#include "fleetnav/sim/simulation.hpp"

namespace fleetnav::sim {
namespace {

struct Record {
  std::vector<RobotTruth> truth;
  std::vector<SensorFrame> frames;
};

WorldDescription Yard() {
  absl::StatusOr<WorldDescription> world =
      LoadWorld(std::string(FLEETNAV_WORLDS_DIR) + "/delivery_yard.yaml");
  EXPECT_TRUE(world.ok()) << world.status();
  // A tall wall at x = -4 keeps the recorded fleet (west) and the added robots (east) out of
  // each other's sight, so that only the noise streams could differ.
  world->boxes.push_back({"wall", {-4.0, 0.0}, {0.2, 30.0}, 0.0, 3.0});
  return *world;
}

// Drives the robots named in `record` (other robots get the same commands but are not
// recorded) for `ticks`.
Record RunFleet(uint64_t seed,
                const std::vector<std::tuple<std::string, std::string, Pose2>>& robots,
                const std::vector<std::string>& recorded, int ticks) {
  SimulationParams params;
  params.seed = seed;
  absl::StatusOr<std::unique_ptr<Simulation>> sim = Simulation::Create(Yard(), params);
  EXPECT_TRUE(sim.ok());
  for (const auto& [id, kind, pose] : robots) EXPECT_TRUE((*sim)->AddRobot(id, kind, pose).ok());
  Record record;
  for (int t = 0; t < ticks; ++t) {
    for (const auto& [id, kind, pose] : robots) {
      absl::StatusOr<SensorFrame> frame = (*sim)->Sense(id);
      EXPECT_TRUE(frame.ok());
      if (std::find(recorded.begin(), recorded.end(), id) != recorded.end()) {
        record.frames.push_back(*frame);
      }
      ActuatorCommand command;
      const double turn = (t / 100) % 2 == 0 ? 0.2 : -0.2;
      if (kind == "ackermann-delivery") {
        command.drive = AckermannDrive{0.6, turn};
      } else {
        command.drive = Twist2{0.3, kind == "mecanum-platform" ? 0.1 : 0.0, turn};
      }
      EXPECT_TRUE((*sim)->Command(id, command).ok());
    }
    (*sim)->Advance();
    for (const RobotTruth& truth : (*sim)->GroundTruth().robots) {
      if (std::find(recorded.begin(), recorded.end(), truth.robot_id) != recorded.end()) {
        record.truth.push_back(truth);
      }
    }
  }
  return record;
}

void ExpectIdentical(const Record& a, const Record& b) {
  ASSERT_EQ(a.truth.size(), b.truth.size());
  for (size_t i = 0; i < a.truth.size(); ++i) {
    ASSERT_EQ(a.truth[i].pose.x_m(), b.truth[i].pose.x_m()) << i;
    ASSERT_EQ(a.truth[i].pose.y_m(), b.truth[i].pose.y_m()) << i;
    ASSERT_EQ(a.truth[i].pose.yaw_rad(), b.truth[i].pose.yaw_rad()) << i;
  }
  ASSERT_EQ(a.frames.size(), b.frames.size());
  for (size_t i = 0; i < a.frames.size(); ++i) {
    const SensorFrame& x = a.frames[i];
    const SensorFrame& y = b.frames[i];
    ASSERT_EQ(x.encoders.size(), y.encoders.size());
    for (size_t k = 0; k < x.encoders.size(); ++k)
      ASSERT_EQ(x.encoders[k].ticks, y.encoders[k].ticks);
    ASSERT_EQ(x.imu.gyro_z_radps, y.imu.gyro_z_radps) << i;
    ASSERT_EQ(x.imu.accel_x_mps2, y.imu.accel_x_mps2) << i;
    ASSERT_EQ(x.ultrasonic.size(), y.ultrasonic.size());
    for (size_t k = 0; k < x.ultrasonic.size(); ++k) {
      ASSERT_EQ(x.ultrasonic[k].range_m, y.ultrasonic[k].range_m);
    }
    ASSERT_EQ(x.lasers.size(), y.lasers.size());
    for (size_t k = 0; k < x.lasers.size(); ++k)
      ASSERT_EQ(x.lasers[k].ranges_m, y.lasers[k].ranges_m);
    ASSERT_EQ(x.gps.has_value(), y.gps.has_value());
    if (x.gps) {
      ASSERT_EQ(x.gps->x_m, y.gps->x_m);
    }
    ASSERT_EQ(x.bumper, y.bumper);
  }
}

const std::vector<std::tuple<std::string, std::string, Pose2>> kFleet = {
    {"lely", "lely-vector", Pose2(-12, -8, 0)},
    {"omni", "mecanum-platform", Pose2(-10, 0, 0)},
    {"car", "ackermann-delivery", Pose2(-16, 4, 0)},
};

TEST(DeterminismTest, SameSeedGivesBitIdenticalTrajectoriesAndSensors) {
  const Record a = RunFleet(42, kFleet, {"lely", "omni", "car"}, 400);
  const Record b = RunFleet(42, kFleet, {"lely", "omni", "car"}, 400);
  ExpectIdentical(a, b);
  // A different seed changes the noise.
  const Record c = RunFleet(43, kFleet, {"lely", "omni", "car"}, 10);
  EXPECT_NE(a.frames[0].imu.gyro_z_radps, c.frames[0].imu.gyro_z_radps);
}

TEST(DeterminismTest, AddingARobotLeavesTheOthersUnchanged) {
  auto bigger = kFleet;
  bigger.emplace_back("late", "ackermann-delivery", Pose2(10, -12, 0));
  bigger.emplace_back("late_lely", "lely-vector", Pose2(0, 10, 0));
  const Record a = RunFleet(7, kFleet, {"lely", "omni", "car"}, 300);
  const Record b = RunFleet(7, bigger, {"lely", "omni", "car"}, 300);
  ExpectIdentical(a, b);
}

}  // namespace
}  // namespace fleetnav::sim
