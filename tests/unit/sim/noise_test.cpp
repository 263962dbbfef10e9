#include "fleetnav/sim/noise.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

namespace fleetnav::sim {
namespace {

TEST(NoiseSeedTest, StableForTheSameInputs) {
  EXPECT_EQ(NoiseSeed(7, "lely1", "gyro"), NoiseSeed(7, "lely1", "gyro"));
}

TEST(NoiseSeedTest, DiffersPerSeedRobotAndSensor) {
  std::set<uint64_t> seeds;
  for (uint64_t seed : {1, 2, 3}) {
    for (const char* robot : {"lely1", "lely2", "a"}) {
      for (const char* sensor : {"gyro", "encoders", "ultrasonic"}) {
        seeds.insert(NoiseSeed(seed, robot, sensor));
      }
    }
  }
  EXPECT_EQ(seeds.size(), 27u);
  // The robot/sensor boundary matters.
  EXPECT_NE(NoiseSeed(1, "ab", "c"), NoiseSeed(1, "a", "bc"));
}

// Sample mean and spread against the closed form, over several seeds.
TEST(NoiseStreamTest, GaussianMatchesItsStddev) {
  constexpr int kSamples = 20000;
  constexpr double kStddev = 0.7;
  for (uint64_t seed = 1; seed <= 5; ++seed) {
    NoiseStream stream(NoiseSeed(seed, "r", "s"));
    double sum = 0.0, sum_sq = 0.0;
    for (int i = 0; i < kSamples; ++i) {
      const double x = stream.Gaussian(kStddev);
      sum += x;
      sum_sq += x * x;
    }
    const double mean = sum / kSamples;
    const double stddev = std::sqrt(sum_sq / kSamples - mean * mean);
    EXPECT_LT(std::abs(mean), 4.0 * kStddev / std::sqrt(kSamples)) << "seed " << seed;
    EXPECT_NEAR(stddev / kStddev, 1.0, 0.05) << "seed " << seed;
  }
}

TEST(NoiseStreamTest, ZeroStddevIsSilentAndUniformInRange) {
  NoiseStream stream(3);
  for (int i = 0; i < 100; ++i) {
    EXPECT_EQ(stream.Gaussian(0.0), 0.0);
    const double u = stream.Uniform();
    EXPECT_GE(u, 0.0);
    EXPECT_LT(u, 1.0);
  }
}

TEST(NoiseStreamTest, SameSeedSameSequence) {
  NoiseStream a(42), b(42), c(43);
  bool any_differs = false;
  for (int i = 0; i < 50; ++i) {
    const double x = a.Gaussian(1.0);
    EXPECT_EQ(x, b.Gaussian(1.0));
    any_differs = any_differs || x != c.Gaussian(1.0);
  }
  EXPECT_TRUE(any_differs);
}

}  // namespace
}  // namespace fleetnav::sim
