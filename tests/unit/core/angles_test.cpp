#include "fleetnav/core/angles.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace fleetnav {
namespace {

constexpr double kTol = 1e-12;

TEST(NormalizeAngleTest, KeepsValuesInsideRange) {
  EXPECT_NEAR(NormalizeAngle(0.0), 0.0, kTol);
  EXPECT_NEAR(NormalizeAngle(1.0), 1.0, kTol);
  EXPECT_NEAR(NormalizeAngle(-1.0), -1.0, kTol);
}

TEST(NormalizeAngleTest, PiIsIncludedMinusPiIsNot) {
  EXPECT_DOUBLE_EQ(NormalizeAngle(kPi), kPi);
  EXPECT_DOUBLE_EQ(NormalizeAngle(-kPi), kPi);
  EXPECT_NEAR(NormalizeAngle(3.0 * kPi), kPi, 1e-9);
  EXPECT_NEAR(NormalizeAngle(-3.0 * kPi), kPi, 1e-9);
}

TEST(NormalizeAngleTest, WrapsMultiplesOfTwoPi) {
  EXPECT_NEAR(NormalizeAngle(2.0 * kPi), 0.0, kTol);
  EXPECT_NEAR(NormalizeAngle(-1.5 * kPi), 0.5 * kPi, kTol);
  EXPECT_NEAR(NormalizeAngle(1.5 * kPi), -0.5 * kPi, kTol);
  EXPECT_NEAR(NormalizeAngle(100.0 * kPi + 0.3), 0.3, 1e-9);
}

TEST(NormalizeAngleTest, RandomAnglesLandInHalfOpenRangeAndKeepDirection) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(-50.0, 50.0);
  for (int i = 0; i < 1000; ++i) {
    const double a = angle(rng);
    const double n = NormalizeAngle(a);
    EXPECT_GT(n, -kPi);
    EXPECT_LE(n, kPi);
    EXPECT_NEAR(std::cos(n), std::cos(a), 1e-9);
    EXPECT_NEAR(std::sin(n), std::sin(a), 1e-9);
  }
}

TEST(NormalizeAngleTest, NanStaysNan) { EXPECT_TRUE(std::isnan(NormalizeAngle(std::nan("")))); }

TEST(AngleDifferenceTest, TakesTheShortWayRound) {
  EXPECT_NEAR(AngleDifference(0.1, -0.1), 0.2, kTol);
  EXPECT_NEAR(AngleDifference(kPi - 0.1, -kPi + 0.1), -0.2, 1e-12);
  EXPECT_NEAR(AngleDifference(-kPi + 0.1, kPi - 0.1), 0.2, 1e-12);
  EXPECT_NEAR(AngleDifference(DegToRad(10), DegToRad(350)), DegToRad(20), 1e-12);
}

TEST(DegRadTest, Converts) {
  EXPECT_DOUBLE_EQ(DegToRad(180.0), kPi);
  EXPECT_DOUBLE_EQ(RadToDeg(kPi / 2.0), 90.0);
  static_assert(DegToRad(0.0) == 0.0);
}

}  // namespace
}  // namespace fleetnav
