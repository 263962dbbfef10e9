// VFH+ on generated laser points with known answers: free space, a box ahead, near-equal gaps,
// the hysteresis of the binary histogram, the turning-circle mask and a wall that blocks all.
#include "fleetnav/robot_agent/control/avoidance/vfh_plus.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <vector>

#include "fleetnav/core/angles.hpp"

namespace fleetnav::agent {
namespace {

/// The outline of an axis-aligned box, one point every 2 cm (what a dense laser returns).
std::vector<Eigen::Vector2d> BoxOutline(double x0, double y0, double x1, double y1) {
  std::vector<Eigen::Vector2d> out;
  for (double t = 0.0; t <= 1.0; t += 0.02 / std::max(x1 - x0, y1 - y0)) {
    out.emplace_back(x0 + t * (x1 - x0), y0);
    out.emplace_back(x0 + t * (x1 - x0), y1);
    out.emplace_back(x0, y0 + t * (y1 - y0));
    out.emplace_back(x1, y0 + t * (y1 - y0));
  }
  return out;
}

/// The least distance from the points to the ray from the origin in direction `angle_rad`,
/// out to `length_m`.
double RayClearance(const std::vector<Eigen::Vector2d>& points, double angle_rad, double length_m) {
  const Eigen::Vector2d u(std::cos(angle_rad), std::sin(angle_rad));
  double best = 1e9;
  for (const Eigen::Vector2d& p : points) {
    const double t = std::clamp(p.dot(u), 0.0, length_m);
    best = std::min(best, (p - t * u).norm());
  }
  return best;
}

TEST(VfhPlusTest, FreeSpaceGoesStraightForTheTarget) {
  VfhPlus vfh{VfhPlusParams{}};
  for (double target_deg : {0.0, 30.0, -50.0}) {
    const std::optional<VfhPlusDirection> d = vfh.Choose({}, DegToRad(target_deg));
    ASSERT_TRUE(d.has_value());
    EXPECT_NEAR(RadToDeg(d->direction_rad), target_deg, 1.5);
    EXPECT_NEAR(d->clearance_m, VfhPlusParams{}.window_radius_m, 1e-9);
  }
}

TEST(VfhPlusTest, SteersPastABoxAheadWithTheRobotRadiusToSpare) {
  const VfhPlusParams params;
  VfhPlus vfh(params);
  const std::vector<Eigen::Vector2d> box = BoxOutline(1.7, -0.3, 2.3, 0.3);
  const std::optional<VfhPlusDirection> d = vfh.Choose(box, 0.0);
  ASSERT_TRUE(d.has_value());
  EXPECT_GT(RayClearance(box, d->direction_rad, params.window_radius_m), params.robot_radius_m);
  // Not further round than the box needs: the valley's border (the box's enlarged edge, 23°)
  // plus half a wide valley (s_max / 2 sectors).
  EXPECT_LT(std::abs(d->direction_rad),
            DegToRad(24.0) + (params.wide_valley_sectors / 2.0 + 1.0) * params.sector_rad);
}

TEST(VfhPlusTest, ChoosesTheGapTowardsTheTargetAmongNearEqualGaps) {
  // Four boxes 0.6 m wide with gaps of 1.00, 1.05 and 1.10 m between them (the capstone's
  // failing case), 1.5 m ahead; the row is slid so that the gap under test is centred 0.3 m
  // left of the heading, and the target points at it.
  const std::vector<double> gaps = {1.00, 1.05, 1.10};
  for (size_t tested = 0; tested < gaps.size(); ++tested) {
    double y = 0.0;
    double centre = 0.0;
    std::vector<std::pair<double, double>> spans;
    for (size_t i = 0; i <= gaps.size(); ++i) {
      spans.emplace_back(y, y + 0.6);
      if (i < gaps.size()) {
        if (i == tested) centre = y + 0.6 + gaps[i] / 2.0;
        y += 0.6 + gaps[i];
      }
    }
    std::vector<Eigen::Vector2d> row;
    for (const auto& [from, to] : spans) {
      for (const Eigen::Vector2d& p :
           BoxOutline(1.5, from - centre + 0.3, 2.1, to - centre + 0.3)) {
        row.push_back(p);
      }
    }
    VfhPlus vfh{VfhPlusParams{}};
    const std::optional<VfhPlusDirection> d = vfh.Choose(row, std::atan2(0.3, 1.5));
    ASSERT_TRUE(d.has_value()) << "gap " << tested;
    // Through the tested gap's middle, not into a box or a neighbouring gap.
    EXPECT_NEAR(std::tan(d->direction_rad) * 1.5, 0.3, gaps[tested] / 2.0 - 0.3) << tested;
    EXPECT_GT(RayClearance(row, d->direction_rad, 2.1), 0.3) << tested;
  }
}

TEST(VfhPlusTest, TheBinaryHistogramHoldsBetweenItsThresholds) {
  const VfhPlusParams params;
  // A box dead ahead whose nearest face moves: in the band between the thresholds a sector
  // keeps what it was.
  const auto box_at = [](double x) { return BoxOutline(x, -0.5, x + 0.4, 0.5); };
  const double between_m = 0.5 * (params.blocked_within_m + params.free_beyond_m);
  VfhPlus fresh(params);
  std::optional<VfhPlusDirection> d = fresh.Choose(box_at(between_m), 0.0);
  ASSERT_TRUE(d.has_value());
  EXPECT_NEAR(d->direction_rad, 0.0, 1e-9) << "never blocked: the way ahead stays open";

  VfhPlus seen_near(params);
  ASSERT_TRUE(seen_near.Choose(box_at(params.blocked_within_m - 0.5), 0.0).has_value());
  d = seen_near.Choose(box_at(between_m), 0.0);
  ASSERT_TRUE(d.has_value());
  EXPECT_GT(std::abs(d->direction_rad), DegToRad(10.0)) << "blocked once: stays blocked";
  d = seen_near.Choose(box_at(params.free_beyond_m + 0.05), 0.0);
  ASSERT_TRUE(d.has_value());
  EXPECT_NEAR(d->direction_rad, 0.0, 1e-9) << "beyond the low threshold: open again";
}

TEST(VfhPlusTest, MasksDirectionsTheTurningCircleCannotReach) {
  VfhPlusParams params;
  params.max_direction_rad = DegToRad(100.0);
  // A post just right of the robot, inside the right turning circle's reach: the narrow gap
  // beyond it (hard right) cannot be driven into without meeting it.
  const std::vector<Eigen::Vector2d> post = BoxOutline(0.45, -0.85, 0.55, -0.75);
  VfhPlus unmasked_params_check(params);
  const std::optional<VfhPlusDirection> d = unmasked_params_check.Choose(post, DegToRad(-95.0));
  ASSERT_TRUE(d.has_value());
  EXPECT_GT(d->direction_rad, std::atan2(-0.8, 0.5)) << RadToDeg(d->direction_rad);

  // With a turning radius so small that the post is outside the circle's reach, hard right
  // is allowed.
  params.min_turning_radius_m = 0.05;
  params.robot_radius_m = 0.05;
  params.safety_distance_m = 0.0;
  VfhPlus tight(params);
  const std::optional<VfhPlusDirection> e = tight.Choose(post, DegToRad(-95.0));
  ASSERT_TRUE(e.has_value());
  EXPECT_LT(e->direction_rad, std::atan2(-0.8, 0.5)) << RadToDeg(e->direction_rad);
}

TEST(VfhPlusTest, AWallAcrossTheWayBlocksEveryDirection) {
  std::vector<Eigen::Vector2d> wall;
  for (double y = -3.0; y <= 3.0; y += 0.02) wall.emplace_back(0.9, y);
  VfhPlus vfh{VfhPlusParams{}};
  EXPECT_FALSE(vfh.Choose(wall, 0.0).has_value());
}

TEST(VfhPlusTest, ValidateNamesBadParameters) {
  EXPECT_TRUE(VfhPlusParams{}.Validate().ok());
  VfhPlusParams p;
  p.free_beyond_m = 1.0;  // below blocked_within_m
  EXPECT_EQ(p.Validate().code(), absl::StatusCode::kInvalidArgument);
  p = VfhPlusParams{};
  p.target_weight = 3.0;  // not > μ2 + μ3
  EXPECT_EQ(p.Validate().code(), absl::StatusCode::kInvalidArgument);
  p = VfhPlusParams{};
  p.sector_rad = -0.1;
  EXPECT_EQ(p.Validate().code(), absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace fleetnav::agent
