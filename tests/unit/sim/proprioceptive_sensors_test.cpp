#include "fleetnav/sim/proprioceptive_sensors.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/sim/simulation.hpp"
#include "sim_test_util.hpp"

namespace fleetnav::sim {
namespace {

using testing::MakeSimulation;
using testing::TwistCommand;

int64_t TicksOf(const SensorFrame& frame, const char* name) {
  const EncoderReading* reading = frame.FindEncoder(name);
  EXPECT_NE(reading, nullptr) << name;
  return reading == nullptr ? 0 : reading->ticks;
}

ProprioceptiveParams Noiseless() {
  ProprioceptiveParams params;
  params.gyro_noise_density_radps_per_sqrt_hz = 0.0;
  params.gyro_bias_walk_radps_per_sqrt_s = 0.0;
  return params;
}

TEST(ProprioceptiveSensorsTest, TicksFromWheelAngles) {
  ProprioceptiveSensors sensors(Noiseless(), 1, "r");
  SensorFrame frame;
  sensors.Sample(2.0 * kPi, 4.0 * kPi + 1e-9, 0.0, 0.02, &frame);
  EXPECT_EQ(TicksOf(frame, "left"), 4096);
  EXPECT_EQ(TicksOf(frame, "right"), 8192);
  // Backwards rolls give negative counts, rounded down.
  sensors.Sample(-kPi, 0.0, 0.0, 0.02, &frame);
  EXPECT_EQ(TicksOf(frame, "left"), -2048);
  EXPECT_EQ(TicksOf(frame, "right"), 0);
  // Half a tick forward is still tick 0.
  sensors.Sample(0.5 * 2.0 * kPi / 4096, -0.5 * 2.0 * kPi / 4096, 0.0, 0.02, &frame);
  EXPECT_EQ(TicksOf(frame, "left"), 0);
  EXPECT_EQ(TicksOf(frame, "right"), -1);
}

TEST(ProprioceptiveSensorsTest, WheelRadiusScaleError) {
  ProprioceptiveParams params = Noiseless();
  params.wheel_radius_scale_error = 0.01;
  ProprioceptiveSensors sensors(params, 1, "r");
  SensorFrame frame;
  sensors.Sample(100 * 2.0 * kPi, 100 * 2.0 * kPi, 0.0, 0.02, &frame);
  EXPECT_NEAR(TicksOf(frame, "left"), 413696, 1);  // 1 % more than 409600
}

TEST(ProprioceptiveSensorsTest, NoiselessGyroIsTheTrueRate) {
  ProprioceptiveSensors sensors(Noiseless(), 1, "r");
  SensorFrame frame;
  for (double rate : {0.0, 0.3, -0.45}) {
    sensors.Sample(0, 0, rate, 0.02, &frame);
    EXPECT_EQ(frame.imu.gyro_z_radps, rate);
  }
}

TEST(ProprioceptiveSensorsTest, NoiseIsPerRobot) {
  ProprioceptiveParams params;
  ProprioceptiveSensors a1(params, 9, "a"), a2(params, 9, "a"), b(params, 9, "b");
  SensorFrame fa1, fa2, fb;
  bool any_differs = false;
  for (int i = 0; i < 20; ++i) {
    a1.Sample(0, 0, 0, 0.02, &fa1);
    a2.Sample(0, 0, 0, 0.02, &fa2);
    b.Sample(0, 0, 0, 0.02, &fb);
    EXPECT_EQ(fa1.imu.gyro_z_radps, fa2.imu.gyro_z_radps);
    any_differs = any_differs || fa1.imu.gyro_z_radps != fb.imu.gyro_z_radps;
  }
  EXPECT_TRUE(any_differs);
}

// Encoders in the simulation: after driving straight a measured distance, each wheel's ticks
// are that distance over the wheel circumference times the resolution (thesis eq. 3.4).
TEST(SimulatedEncodersTest, TicksMatchTheDistanceDriven) {
  std::unique_ptr<Simulation> sim = MakeSimulation(3);
  ASSERT_TRUE(sim->AddRobot("lely1", "lely-vector", Pose2(1, 2, DegToRad(60))).ok());
  absl::StatusOr<SensorFrame> first = sim->Sense("lely1");
  ASSERT_TRUE(first.ok()) << first.status();
  EXPECT_FALSE(first->steering_angle_rad.has_value()) << "a differential drive does not steer";
  const Pose2 start = sim->GroundTruth().robots.at(0).pose;

  ASSERT_TRUE(sim->Command("lely1", TwistCommand(0.3, 0.0)).ok());
  for (int i = 0; i < 400; ++i) sim->Advance();  // 8 s
  ASSERT_TRUE(sim->Command("lely1", TwistCommand(0.0, 0.0)).ok());
  for (int i = 0; i < 100; ++i) sim->Advance();  // stop

  absl::StatusOr<SensorFrame> last = sim->Sense("lely1");
  ASSERT_TRUE(last.ok()) << last.status();
  const Pose2 end = sim->GroundTruth().robots.at(0).pose;
  const double distance_m = (end.translation() - start.translation()).norm();
  ASSERT_GT(distance_m, 2.0);
  const double expected_ticks = distance_m / (2.0 * kPi * 0.15) * 4096;
  const double left = static_cast<double>(TicksOf(*last, "left") - TicksOf(*first, "left"));
  const double right = static_cast<double>(TicksOf(*last, "right") - TicksOf(*first, "right"));
  std::printf("[ figures  ] encoders over %.4f m: left %+.3f %%, right %+.3f %% of expected\n",
              distance_m, 100.0 * (left / expected_ticks - 1.0),
              100.0 * (right / expected_ticks - 1.0));
  EXPECT_GT(left, 0.0);
  EXPECT_GT(right, 0.0);
  EXPECT_NEAR(left, expected_ticks, 0.01 * expected_ticks);
  EXPECT_NEAR(right, expected_ticks, 0.01 * expected_ticks);
}

TEST(SimulatedEncodersTest, TurningLeftRunsTheRightWheelForward) {
  std::unique_ptr<Simulation> sim = MakeSimulation(3);
  ASSERT_TRUE(sim->AddRobot("lely1", "lely-vector", Pose2(0, 0, 0)).ok());
  absl::StatusOr<SensorFrame> first = sim->Sense("lely1");
  ASSERT_TRUE(first.ok());
  ASSERT_TRUE(sim->Command("lely1", TwistCommand(0.0, 0.3)).ok());
  double turned_rad = 0.0;
  double last_yaw = sim->GroundTruth().robots.at(0).pose.yaw_rad();
  for (int i = 0; i < 250; ++i) {
    sim->Advance();
    const double yaw = sim->GroundTruth().robots.at(0).pose.yaw_rad();
    turned_rad += AngleDifference(yaw, last_yaw);
    last_yaw = yaw;
  }
  absl::StatusOr<SensorFrame> last = sim->Sense("lely1");
  ASSERT_TRUE(last.ok());
  const double left = static_cast<double>(TicksOf(*last, "left") - TicksOf(*first, "left"));
  const double right = static_cast<double>(TicksOf(*last, "right") - TicksOf(*first, "right"));
  EXPECT_LT(left, 0.0);
  EXPECT_GT(right, 0.0);
  // Each wheel rolls turned × track / 2 (eq. 3.2), a few % of skid allowed.
  const double expected_ticks = turned_rad * 0.46 / (2.0 * kPi * 0.15) * 4096;
  EXPECT_GT(turned_rad, 1.0);
  EXPECT_NEAR(right, expected_ticks, 0.03 * expected_ticks);
  EXPECT_NEAR(-left, expected_ticks, 0.03 * expected_ticks);
}

// The gyro of a robot standing still: zero mean (white noise plus a slow bias walk) and a
// spread of noise_density / √period, over several seeds.
TEST(SimulatedGyroTest, StillRobotNoiseMatchesTheDensity) {
  constexpr int kSamples = 2000;
  const SimulationParams defaults;
  const double period_s = defaults.control_period_s;
  const double sigma = defaults.sensors.gyro_noise_density_radps_per_sqrt_hz / std::sqrt(period_s);
  // The bias walk over the whole run (4σ of its end value) bounds its share of the mean.
  const double bias_allowance =
      4.0 * defaults.sensors.gyro_bias_walk_radps_per_sqrt_s * std::sqrt(kSamples * period_s);
  for (uint64_t seed : {1, 2, 3, 17, 1234}) {
    std::unique_ptr<Simulation> sim = MakeSimulation(seed);
    ASSERT_TRUE(sim->AddRobot("lely1", "lely-vector", Pose2(0, 0, 0)).ok());
    double sum = 0.0, sum_sq = 0.0;
    for (int i = 0; i < kSamples; ++i) {
      absl::StatusOr<SensorFrame> frame = sim->Sense("lely1");
      ASSERT_TRUE(frame.ok());
      sum += frame->imu.gyro_z_radps;
      sum_sq += frame->imu.gyro_z_radps * frame->imu.gyro_z_radps;
      sim->Advance();
    }
    const double mean = sum / kSamples;
    const double stddev = std::sqrt((sum_sq - kSamples * mean * mean) / (kSamples - 1));
    std::printf("[ figures  ] gyro seed %llu: mean %.3e rad/s (bound %.3e), std/expected %.4f\n",
                static_cast<unsigned long long>(seed), mean,
                3.0 * sigma / std::sqrt(kSamples) + bias_allowance, stddev / sigma);
    EXPECT_LT(std::abs(mean), 3.0 * sigma / std::sqrt(kSamples) + bias_allowance)
        << "seed " << seed;
    EXPECT_NEAR(stddev / sigma, 1.0, 0.15) << "seed " << seed;
  }
}

}  // namespace
}  // namespace fleetnav::sim
