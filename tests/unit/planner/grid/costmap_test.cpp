#include "fleetnav/planner/grid/costmap.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/robot_model.hpp"

namespace fleetnav::planner {
namespace {

OccupancyGrid EmptyGrid(int w, int h, double res) {
  return OccupancyGrid::Filled(w, h, res, Pose2(), OccupancyGrid::kFreeValue).value();
}

std::vector<Eigen::Vector2d> Rectangle(double front, double back, double half_width) {
  return {{front, -half_width}, {front, half_width}, {-back, half_width}, {-back, -half_width}};
}

TEST(DistanceTransformTest, MatchesBruteForceOnRandomGrids) {
  for (uint64_t seed = 0; seed < 5; ++seed) {
    std::mt19937_64 rng(seed);
    std::bernoulli_distribution occupied(0.05);
    const int w = 23, h = 17;
    std::vector<uint8_t> obstacle(w * h);
    for (auto& o : obstacle) o = occupied(rng);
    obstacle[5] = 1;
    const std::vector<double> d2 = SquaredDistanceTransform(obstacle, w, h);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        double best = 1e30;
        for (int oy = 0; oy < h; ++oy) {
          for (int ox = 0; ox < w; ++ox) {
            if (obstacle[oy * w + ox])
              best = std::min(best, double((ox - x) * (ox - x) + (oy - y) * (oy - y)));
          }
        }
        ASSERT_DOUBLE_EQ(d2[y * w + x], best) << "seed " << seed << " cell " << x << "," << y;
      }
    }
  }
}

TEST(CostmapTest, ElongatedFootprintDependsOnYaw) {
  OccupancyGrid grid = EmptyGrid(40, 40, 0.1);
  grid.SetValue({26, 20}, OccupancyGrid::kOccupiedValue);  // 0.6 m ahead of cell (20, 20)
  absl::StatusOr<Costmap> map = Costmap::Build(grid, Rectangle(0.8, 0.2, 0.15), CostmapParams{});
  ASSERT_TRUE(map.ok()) << map.status();
  EXPECT_FALSE(map->FootprintFree(20, 20, 0.0));     // nose over the obstacle
  EXPECT_TRUE(map->FootprintFree(20, 20, kPi / 2));  // turned away
  EXPECT_TRUE(map->FootprintFree(20, 20, kPi));      // short tail side is 0.2 m
  EXPECT_FALSE(map->FootprintFree(26, 20, 1.0));     // on the obstacle
  // A circle through the inscribed radius would miss the nose: the test is not circular.
  EXPECT_LT(map->inscribed_radius_m(), 0.6);
  EXPECT_NEAR(map->DistanceToObstacle_m(20, 20), 0.6, 1e-6);
}

TEST(CostmapTest, UnknownPolicyDecidesUnknownCellsAndTheOutside) {
  OccupancyGrid grid = EmptyGrid(20, 20, 0.1);
  grid.SetValue({12, 10}, OccupancyGrid::kUnknownValue);
  const auto fp = Rectangle(0.25, 0.25, 0.1);
  CostmapParams strict;
  absl::StatusOr<Costmap> a = Costmap::Build(grid, fp, strict);
  ASSERT_TRUE(a.ok());
  EXPECT_TRUE(a->IsObstacle(12, 10));
  EXPECT_FALSE(a->FootprintFree(10, 10, 0.0));
  EXPECT_FALSE(a->FootprintFree(1, 10, 0.0));  // hangs over the edge into unknown space
  CostmapParams lenient;
  lenient.unknown = UnknownPolicy::kFree;
  absl::StatusOr<Costmap> b = Costmap::Build(grid, fp, lenient);
  ASSERT_TRUE(b.ok());
  EXPECT_FALSE(b->IsObstacle(12, 10));
  EXPECT_TRUE(b->FootprintFree(10, 10, 0.0));
  EXPECT_TRUE(b->FootprintFree(1, 10, 0.0));
}

TEST(CostmapTest, NeverCallsAPoseFreeWhenAnObstacleCellCentreIsUnderTheFootprint) {
  // Lely footprint, random obstacles, yaws at bin centres: compare with an exact point-in-
  // polygon test on every obstacle cell centre.
  const RobotModel lely = LelyVectorModel();
  CostmapParams params;
  params.orientation_bins = 16;
  for (uint64_t seed = 0; seed < 3; ++seed) {
    std::mt19937_64 rng(seed);
    OccupancyGrid grid = EmptyGrid(80, 80, 0.1);
    std::uniform_int_distribution<int> cell(0, 79);
    for (int k = 0; k < 40; ++k)
      grid.SetValue({cell(rng), cell(rng)}, OccupancyGrid::kOccupiedValue);
    absl::StatusOr<Costmap> map = Costmap::Build(grid, lely.footprint_m, params);
    ASSERT_TRUE(map.ok()) << map.status();
    std::uniform_int_distribution<int> bin(0, 15);
    std::uniform_int_distribution<int> inner(20, 59);
    int collisions = 0;
    for (int trial = 0; trial < 300; ++trial) {
      const int x = inner(rng), y = inner(rng);
      const double yaw = 2 * kPi * bin(rng) / 16;
      bool exact_hit = false;
      const double c = std::cos(yaw), s = std::sin(yaw);
      for (int oy = 0; oy < 80 && !exact_hit; ++oy) {
        for (int ox = 0; ox < 80 && !exact_hit; ++ox) {
          if (!map->IsObstacle(ox, oy)) continue;
          // Obstacle centre in the robot frame.
          const double dx = (ox - x) * 0.1, dy = (oy - y) * 0.1;
          const Eigen::Vector2d p(c * dx + s * dy, -s * dx + c * dy);
          bool inside = false;
          const auto& poly = lely.footprint_m;
          for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
            if ((poly[i].y() > p.y()) != (poly[j].y() > p.y()) &&
                p.x() < (poly[j].x() - poly[i].x()) * (p.y() - poly[i].y()) /
                                (poly[j].y() - poly[i].y()) +
                            poly[i].x()) {
              inside = !inside;
            }
          }
          exact_hit = inside;
        }
      }
      if (exact_hit) {
        ++collisions;
        EXPECT_FALSE(map->FootprintFree(x, y, yaw)) << x << "," << y << " yaw " << yaw;
      }
    }
    EXPECT_GT(collisions, 0);
  }
}

TEST(CostmapTest, RejectsBadParamsAndFootprints) {
  const OccupancyGrid grid = EmptyGrid(10, 10, 0.1);
  CostmapParams bad;
  bad.orientation_bins = 0;
  EXPECT_EQ(Costmap::Build(grid, Rectangle(1, 1, 1), bad).status().code(),
            absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(Costmap::Build(grid, {{0, 0}, {1, 0}}, CostmapParams{}).status().code(),
            absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace fleetnav::planner
