#include "fleetnav/sim/geometry2d.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "fleetnav/core/angles.hpp"

namespace fleetnav::sim {
namespace {

TEST(Geometry2dTest, RayHitsBoxFaceWithOutwardNormal) {
  const Shape2 box = BoxShape({5, 0}, {2, 4}, 0.0, 1.0, -1);
  const auto hit = CastRay(box, {0, 0}, {1, 0}, 10.0);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->distance_m, 4.0, 1e-12);
  EXPECT_NEAR(hit->normal.x(), -1.0, 1e-12);
  EXPECT_FALSE(CastRay(box, {0, 0}, {1, 0}, 3.9).has_value());
  EXPECT_FALSE(CastRay(box, {0, 0}, {-1, 0}, 10.0).has_value());
  EXPECT_FALSE(CastRay(box, {0, 3}, {1, 0}, 10.0).has_value());
}

TEST(Geometry2dTest, RayHitsRotatedBoxAndCircle) {
  const Shape2 diamond = BoxShape({3, 0}, {std::sqrt(2.0), std::sqrt(2.0)}, kPi / 4, 1.0, -1);
  const auto hit = CastRay(diamond, {0, 0}, {1, 0}, 10.0);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->distance_m, 2.0, 1e-9);
  const Shape2 circle = CircleShape({0, 4}, 0.5, 1.0, -1);
  const auto c = CastRay(circle, {0, 0}, {0, 1}, 10.0);
  ASSERT_TRUE(c.has_value());
  EXPECT_NEAR(c->distance_m, 3.5, 1e-12);
  EXPECT_NEAR(c->normal.y(), -1.0, 1e-12);
  EXPECT_FALSE(CastRay(circle, {0.6, 0}, {0, 1}, 10.0).has_value());
}

TEST(Geometry2dTest, OverlapAndContainment) {
  const Shape2 a = BoxShape({0, 0}, {2, 2}, 0.0, 1.0, -1);
  EXPECT_TRUE(Overlap(a, BoxShape({1.9, 0}, {2, 2}, 0.3, 1.0, -1)));
  EXPECT_FALSE(Overlap(a, BoxShape({2.5, 0}, {0.8, 0.8}, 0.0, 1.0, -1)));
  EXPECT_TRUE(Overlap(a, CircleShape({1.2, 0}, 0.25, 1.0, -1)));
  // Near the corner: inside the bounding boxes but outside the rounded distance.
  EXPECT_FALSE(Overlap(a, CircleShape({1.3, 1.3}, 0.4, 1.0, -1)));
  EXPECT_TRUE(Contains(a, {0.9, -0.9}));
  EXPECT_FALSE(Contains(a, {1.1, 0}));
  const Shape2 grown =
      FootprintShape({{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}, Pose2(0, 0, 0), 1.0, 0, 0.1);
  EXPECT_TRUE(Contains(grown, {1.05, 1.05}));
}

TEST(Geometry2dTest, PolygonDistanceIsZeroOnOverlapAndExactApart) {
  const Shape2 a = BoxShape({0, 0}, {2, 2}, 0.0, 1.0, 0);
  const Shape2 apart = BoxShape({5, 0.5}, {2, 2}, 0.0, 1.0, 1);
  const Shape2 corner = BoxShape({3, 3}, {2, 2}, 0.0, 1.0, 1);
  const Shape2 rotated = BoxShape({1.5, 0}, {2, 2}, 0.3, 1.0, 1);
  EXPECT_NEAR(PolygonDistance(a, apart), 3.0, 1e-9);
  EXPECT_NEAR(PolygonDistance(apart, a), 3.0, 1e-9);
  EXPECT_NEAR(PolygonDistance(a, corner), std::sqrt(2.0), 1e-9);
  EXPECT_EQ(PolygonDistance(a, rotated), 0.0);
}

TEST(Geometry2dTest, ClipSegmentAndStrip) {
  const auto clip = ClipSegment({0, 0}, {10, 0}, {2, -1}, {4, 1});
  ASSERT_TRUE(clip.has_value());
  EXPECT_NEAR(clip->first, 0.2, 1e-12);
  EXPECT_NEAR(clip->second, 0.4, 1e-12);
  EXPECT_FALSE(ClipSegment({0, 2}, {10, 2}, {2, -1}, {4, 1}).has_value());
  EXPECT_TRUE(OnSegmentStrip({0, 0}, {10, 0}, 0.025, {5, 0.024}));
  EXPECT_FALSE(OnSegmentStrip({0, 0}, {10, 0}, 0.025, {5, 0.026}));
  EXPECT_FALSE(OnSegmentStrip({0, 0}, {10, 0}, 0.025, {10.01, 0}));
}

}  // namespace
}  // namespace fleetnav::sim
