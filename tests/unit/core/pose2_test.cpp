#include "fleetnav/core/pose2.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "fleetnav/core/angles.hpp"

namespace fleetnav {
namespace {

constexpr double kTolM = 1e-9;
constexpr double kTolRad = 1e-9;

void ExpectPoseNear(const Pose2& actual, const Pose2& expected) {
  EXPECT_TRUE(actual.IsNear(expected, kTolM, kTolRad))
      << actual.DebugString() << " vs " << expected.DebugString();
}

std::vector<Pose2> RandomPoses(int count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> xy(-20.0, 20.0);
  std::uniform_real_distribution<double> yaw(-kPi, kPi);
  std::vector<Pose2> poses;
  for (int i = 0; i < count; ++i) poses.emplace_back(xy(rng), xy(rng), yaw(rng));
  return poses;
}

TEST(Pose2Test, DefaultIsIdentity) {
  const Pose2 pose;
  EXPECT_EQ(pose.x_m(), 0.0);
  EXPECT_EQ(pose.y_m(), 0.0);
  EXPECT_EQ(pose.yaw_rad(), 0.0);
}

TEST(Pose2Test, ConstructorNormalizesYaw) {
  EXPECT_NEAR(Pose2(0, 0, 3.0 * kPi / 2.0).yaw_rad(), -kPi / 2.0, 1e-12);
  EXPECT_DOUBLE_EQ(Pose2(0, 0, -kPi).yaw_rad(), kPi);
}

TEST(Pose2Test, ComposeKnownValues) {
  // Robot at (1, 2) facing +y; a point 1 m ahead of it is at (1, 3).
  const Pose2 robot(1.0, 2.0, kPi / 2.0);
  ExpectPoseNear(robot * Pose2(1.0, 0.0, 0.0), Pose2(1.0, 3.0, kPi / 2.0));
  ExpectPoseNear(robot * Pose2(0.0, 1.0, kPi / 2.0), Pose2(0.0, 2.0, kPi));
  const Eigen::Vector2d p = robot.TransformPoint({2.0, 0.5});
  EXPECT_NEAR(p.x(), 0.5, 1e-12);
  EXPECT_NEAR(p.y(), 4.0, 1e-12);
}

TEST(Pose2Test, ComposedYawWraps) {
  const Pose2 a(0, 0, 3.0);
  const Pose2 b(0, 0, 3.0);
  EXPECT_NEAR((a * b).yaw_rad(), 6.0 - 2.0 * kPi, 1e-12);
}

TEST(Pose2Test, TimesInverseIsIdentity) {
  for (const Pose2& a : RandomPoses(200, 11)) {
    ExpectPoseNear(a * a.Inverse(), Pose2());
    ExpectPoseNear(a.Inverse() * a, Pose2());
    ExpectPoseNear(a.Inverse().Inverse(), a);
  }
}

TEST(Pose2Test, CompositionIsAssociative) {
  const std::vector<Pose2> poses = RandomPoses(300, 42);
  for (size_t i = 0; i + 2 < poses.size(); i += 3) {
    const Pose2& a = poses[i];
    const Pose2& b = poses[i + 1];
    const Pose2& c = poses[i + 2];
    ExpectPoseNear((a * b) * c, a * (b * c));
  }
}

TEST(Pose2Test, BetweenRecoversRelativePose) {
  const std::vector<Pose2> poses = RandomPoses(200, 5);
  for (size_t i = 0; i + 1 < poses.size(); i += 2) {
    const Pose2& a = poses[i];
    const Pose2& b = poses[i + 1];
    const Pose2 a_to_b = Between(a, b);
    ExpectPoseNear(a * a_to_b, b);
    ExpectPoseNear(Between(b, a), a_to_b.Inverse());
  }
  ExpectPoseNear(Between(Pose2(1, 0, kPi / 2), Pose2(1, 1, kPi / 2)), Pose2(1, 0, 0));
}

TEST(Pose2Test, TransformPointMatchesComposition) {
  for (const Pose2& a : RandomPoses(100, 3)) {
    const Eigen::Vector2d p(0.7, -1.3);
    const Eigen::Vector2d via_compose = (a * Pose2(p.x(), p.y(), 0.0)).translation();
    EXPECT_NEAR((a.TransformPoint(p) - via_compose).norm(), 0.0, 1e-9);
  }
}

TEST(Pose2Test, IsometryRoundTrip) {
  for (const Pose2& a : RandomPoses(100, 9)) {
    const Eigen::Isometry2d iso = a.ToIsometry();
    ExpectPoseNear(Pose2::FromIsometry(iso), a);
    const Eigen::Vector2d p(2.0, 3.0);
    EXPECT_NEAR((iso * p - a.TransformPoint(p)).norm(), 0.0, 1e-9);
  }
}

TEST(Pose2Test, IsNearComparesAcrossTheWrap) {
  const Pose2 a(0, 0, kPi - 1e-6);
  const Pose2 b(0, 0, -kPi + 1e-6);
  EXPECT_TRUE(a.IsNear(b, 1e-9, 1e-5));
  EXPECT_FALSE(a.IsNear(b, 1e-9, 1e-7));
  EXPECT_FALSE(Pose2(0, 0, 0).IsNear(Pose2(0.1, 0, 0), 0.05, 1.0));
}

TEST(Pose2Test, IsFinite) {
  EXPECT_TRUE(Pose2(1, 2, 3).IsFinite());
  EXPECT_FALSE(Pose2(std::numeric_limits<double>::quiet_NaN(), 0, 0).IsFinite());
  EXPECT_FALSE(Pose2(0, std::numeric_limits<double>::infinity(), 0).IsFinite());
  EXPECT_FALSE(Pose2(0, 0, std::numeric_limits<double>::quiet_NaN()).IsFinite());
}

TEST(Pose2Test, DebugStringShowsComponents) {
  EXPECT_THAT(Pose2(1.5, -2.0, 0.25).DebugString(),
              ::testing::AllOf(::testing::HasSubstr("1.5"), ::testing::HasSubstr("-2.0"),
                               ::testing::HasSubstr("0.25")));
}

}  // namespace
}  // namespace fleetnav
