#include "fleetnav/localization/particle_filter.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/localization/motion_model.hpp"
#include "fleetnav/localization/random.hpp"

namespace fleetnav::localization {
namespace {

TEST(RandomTest, NormalQuantileKnownValues) {
  EXPECT_NEAR(NormalQuantile(0.5), 0.0, 1e-12);
  EXPECT_NEAR(NormalQuantile(0.99), 2.326347874, 1e-8);
  EXPECT_NEAR(NormalQuantile(0.01), -2.326347874, 1e-8);
  EXPECT_NEAR(NormalQuantile(0.975), 1.959963985, 1e-8);
}

TEST(RandomTest, NormalMomentsAndSeeding) {
  Rng rng(42);
  double sum = 0.0, sq = 0.0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const double v = rng.Normal();
    sum += v;
    sq += v * v;
  }
  EXPECT_NEAR(sum / n, 0.0, 0.01);
  EXPECT_NEAR(sq / n, 1.0, 0.02);
  Rng a(7), b(7);
  EXPECT_EQ(a.Next(), b.Next());
}

TEST(KldTest, UsesTheQuantile) {
  // Fox 2003: k = 2 bins, ε = 0.05, δ = 0.01 → about 1/(2ε)·χ²(1; 0.99) ≈ 66.
  EXPECT_NEAR(static_cast<double>(KldSampleCount(2, 0.05, 0.01)), 66.0, 3.0);
  EXPECT_EQ(KldSampleCount(1, 0.05, 0.01), 1u);
  // Grows roughly linearly with k (the cube term shrinks towards 1 as k grows).
  const double n100 = static_cast<double>(KldSampleCount(100, 0.05, 0.01));
  const double n1000 = static_cast<double>(KldSampleCount(1000, 0.05, 0.01));
  EXPECT_GT(n1000 / n100, 7.0);
  EXPECT_LT(n1000 / n100, 10.0);
}

TEST(ResampleTest, SystematicFollowsWeights) {
  std::vector<double> w = {0.1, 0.0, 0.6, 0.3};
  Rng rng(3);
  std::vector<uint32_t> idx;
  SystematicResample(w, 1000, rng, idx);
  std::vector<int> counts(4, 0);
  for (uint32_t i : idx) ++counts[i];
  EXPECT_NEAR(counts[0], 100, 1);
  EXPECT_EQ(counts[1], 0);
  EXPECT_NEAR(counts[2], 600, 1);
  EXPECT_NEAR(counts[3], 300, 1);
  EXPECT_TRUE(std::is_sorted(idx.begin(), idx.end()));
  EXPECT_NEAR(EffectiveSampleSize({0.25, 0.25, 0.25, 0.25}), 4.0, 1e-12);
}

TEST(ClusterTest, FindsHeaviestCluster) {
  ParticleSet p;
  p.Resize(300);
  for (size_t i = 0; i < 300; ++i) {
    const bool a = i < 200;
    p.x_m[i] = a ? 1.0f + 0.01f * (i % 10) : 8.0f;
    p.y_m[i] = a ? 2.0f : -3.0f;
    p.yaw_rad[i] = 0.1f;
    p.weight[i] = 1.0 / 300;
  }
  const auto clusters = ClusterParticles(p, 0.5, 0.5);
  ASSERT_EQ(clusters.size(), 2u);
  EXPECT_NEAR(clusters[0].mean.x_m(), 1.045, 1e-3);
  EXPECT_NEAR(clusters[0].weight, 2.0 / 3.0, 1e-9);
  EXPECT_EQ(CountOccupiedBins(p, 0.5, 0.5), 2u);
}

// Sampled motion: the mean follows the odometry and the spread matches the alphas.
TEST(MotionModelTest, DifferentialMeanAndSpread) {
  MotionModelParams params;
  params.alpha1 = 0.0;
  params.alpha2 = 0.0;
  params.alpha3 = 0.01;  // σ_trans = 0.1·trans
  params.alpha4 = 0.0;
  const size_t n = 20000;
  std::vector<float> x(n, 0.0f), y(n, 0.0f), yaw(n, 0.0f);
  Rng rng(11);
  SampleMotion(params, Pose2(0, 0, 0), Pose2(1.0, 0, 0), rng, x.data(), y.data(), yaw.data(), n);
  const double mean = std::accumulate(x.begin(), x.end(), 0.0) / n;
  double var = 0.0;
  for (float v : x) var += (v - mean) * (v - mean);
  EXPECT_NEAR(mean, 1.0, 0.005);
  EXPECT_NEAR(std::sqrt(var / n), 0.1, 0.005);
}

TEST(MotionModelTest, OmniStrafesAndAckermannTurns) {
  MotionModelParams params;
  params.kinematics = Kinematics::kOmnidirectional;
  params.alpha1 = params.alpha2 = params.alpha3 = params.alpha4 = params.alpha5 = 0.0;
  float x = 0, y = 0, yaw = static_cast<float>(kPi / 2);
  Rng rng(1);
  // Odometry strafes left 1 m; the particle faces +y so it moves towards −x.
  SampleMotion(params, Pose2(0, 0, 0), Pose2(0, 1, 0), rng, &x, &y, &yaw, 1);
  EXPECT_NEAR(x, -1.0, 1e-5);
  EXPECT_NEAR(y, 0.0, 1e-5);
  params.kinematics = Kinematics::kAckermann;
  x = y = yaw = 0;
  SampleMotion(params, Pose2(0, 0, 0), Pose2(1.0, 0.1, 0.2), rng, &x, &y, &yaw, 1);
  EXPECT_NEAR(yaw, 0.2, 1e-5);
  EXPECT_NEAR(x, 1.0, 0.02);
  EXPECT_NEAR(y, 0.1, 0.02);
  params.alpha1 = -1.0;
  EXPECT_FALSE(params.Validate().ok());
}

}  // namespace
}  // namespace fleetnav::localization
