#include "fleetnav/sim/world_description.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "fleetnav/core/angles.hpp"

namespace fleetnav::sim {
namespace {

using ::testing::HasSubstr;

void ExpectInvalid(const absl::StatusOr<WorldDescription>& result, const std::string& needle) {
  ASSERT_FALSE(result.ok()) << "expected an error containing '" << needle << "'";
  EXPECT_EQ(result.status().code(), absl::StatusCode::kInvalidArgument) << result.status();
  EXPECT_THAT(std::string(result.status().message()), HasSubstr(needle));
}

constexpr char kExtent[] = "extent: {min: [-5, -4], max: [5, 4]}\n";

std::string WithExtent(const std::string& rest) { return std::string(kExtent) + rest; }

TEST(WorldDescriptionTest, LoadsTheShippedBarn) {
  absl::StatusOr<WorldDescription> barn =
      LoadWorld(std::string(FLEETNAV_WORLDS_DIR) + "/barn.yaml");
  ASSERT_TRUE(barn.ok()) << barn.status();
  EXPECT_EQ(barn->name, "barn");
  EXPECT_EQ(barn->min_corner_m, Eigen::Vector2d(-13, -13));
  EXPECT_EQ(barn->max_corner_m, Eigen::Vector2d(13, 13));
  // 4 walls + 9 fence segments + the feed kitchen and two cubicle rows.
  ASSERT_EQ(barn->boxes.size(), 16u);
  EXPECT_EQ(barn->boxes[0].kind, "wall");
  EXPECT_EQ(barn->boxes[4].kind, "fence");
  EXPECT_EQ(barn->boxes[13].kind, "feed_kitchen");
  // The north feed fence: a 19 m segment along x at y = 5.9, 0.1 m thick, 1.2 m high.
  const BoxObstacle& fence = barn->boxes[4];
  EXPECT_NEAR(fence.center_m.x(), 0.5, 1e-12);
  EXPECT_NEAR(fence.center_m.y(), 5.9, 1e-12);
  EXPECT_NEAR(fence.size_m.x(), 19.0, 1e-12);
  EXPECT_NEAR(fence.size_m.y(), 0.1, 1e-12);
  EXPECT_NEAR(fence.yaw_rad, 0.0, 1e-12);
  EXPECT_NEAR(fence.height_m, 1.2, 1e-12);
  // A wall along y is yawed by 90°.
  EXPECT_NEAR(barn->boxes[2].yaw_rad, kPi / 2.0, 1e-12);
  EXPECT_NEAR(barn->boxes[2].size_m.x(), 26.0, 1e-12);
  ASSERT_EQ(barn->cylinders.size(), 5u);
  EXPECT_EQ(barn->cylinders[0].kind, "charging_pole");
  EXPECT_NEAR(barn->cylinders[0].radius_m, 0.15, 1e-12);
  ASSERT_EQ(barn->stripes.size(), 9u);
  for (size_t i = 0; i < 9; ++i) EXPECT_EQ(barn->stripes[i].id, static_cast<int>(i) + 1);
  for (size_t i = 0; i < 8; ++i) EXPECT_FALSE(barn->stripes[i].charger);
  EXPECT_TRUE(barn->stripes[8].charger);
  EXPECT_EQ(barn->stripes[0].id, 1);
  EXPECT_NEAR(barn->stripes[0].width_m, 0.05, 1e-12);  // the default
  ASSERT_EQ(barn->markers.size(), 3u);
  EXPECT_EQ(barn->markers[1].id, 2);
  EXPECT_EQ(barn->markers[1].position_m, Eigen::Vector2d(5.0, 4.7));
  ASSERT_EQ(barn->robots.size(), 1u);
  EXPECT_EQ(barn->robots[0].robot_id, "lely1");
  EXPECT_EQ(barn->robots[0].kind_name, "lely-vector");
  EXPECT_TRUE(barn->robots[0].pose.IsNear(Pose2(-5.5, 0.0, 0.0), 1e-12, 1e-12));
}

TEST(WorldDescriptionTest, MissingFileIsNotFound) {
  EXPECT_EQ(LoadWorld(std::string(FLEETNAV_WORLDS_DIR) + "/no-such-world.yaml").status().code(),
            absl::StatusCode::kNotFound);
}

TEST(WorldDescriptionTest, ExtentAloneIsAnEmptyWorld) {
  absl::StatusOr<WorldDescription> world = ParseWorldYaml(kExtent);
  ASSERT_TRUE(world.ok()) << world.status();
  EXPECT_EQ(world->name, "world");
  EXPECT_EQ(world->min_corner_m, Eigen::Vector2d(-5, -4));
  EXPECT_EQ(world->max_corner_m, Eigen::Vector2d(5, 4));
  EXPECT_TRUE(world->boxes.empty());
  EXPECT_TRUE(world->cylinders.empty());
  EXPECT_TRUE(world->stripes.empty());
  EXPECT_TRUE(world->markers.empty());
  EXPECT_TRUE(world->robots.empty());
}

TEST(WorldDescriptionTest, SectionsAreIndependentlyOptional) {
  absl::StatusOr<WorldDescription> world =
      ParseWorldYaml(WithExtent("cylinders: [{center: [1, 2], radius: 0.3}]\n"));
  ASSERT_TRUE(world.ok()) << world.status();
  ASSERT_EQ(world->cylinders.size(), 1u);
  EXPECT_EQ(world->cylinders[0].center_m, Eigen::Vector2d(1, 2));
  EXPECT_DOUBLE_EQ(world->cylinders[0].radius_m, 0.3);
  EXPECT_DOUBLE_EQ(world->cylinders[0].height_m, 1.5);
  EXPECT_EQ(world->cylinders[0].kind, "post");
}

TEST(WorldDescriptionTest, WallDefaultsAndBoxYaw) {
  absl::StatusOr<WorldDescription> world = ParseWorldYaml(
      WithExtent("walls: [{from: [0, 0], to: [0, 3]}]\n"
                 "boxes: [{center: [1, 1], size: [2, 1], yaw_deg: 30, kind: shelf}]\n"
                 "robots: [{id: r1, kind: lely-vector, pose: [1, 2, 90]}]\n"));
  ASSERT_TRUE(world.ok()) << world.status();
  ASSERT_EQ(world->boxes.size(), 2u);
  EXPECT_DOUBLE_EQ(world->boxes[0].size_m.y(), 0.2);  // default wall thickness
  EXPECT_DOUBLE_EQ(world->boxes[0].height_m, 2.5);    // default wall height
  EXPECT_NEAR(world->boxes[0].center_m.y(), 1.5, 1e-12);
  EXPECT_EQ(world->boxes[1].kind, "shelf");
  EXPECT_NEAR(world->boxes[1].yaw_rad, DegToRad(30), 1e-12);
  ASSERT_EQ(world->robots.size(), 1u);
  EXPECT_NEAR(world->robots[0].pose.yaw_rad(), kPi / 2.0, 1e-12);
}

TEST(WorldDescriptionTest, MissingExtent) {
  ExpectInvalid(ParseWorldYaml("name: x\nwalls: []\n"), "extent");
}

TEST(WorldDescriptionTest, BadExtent) {
  ExpectInvalid(ParseWorldYaml("extent: {min: [0, 0]}\n"), "extent.max");
  ExpectInvalid(ParseWorldYaml("extent: {min: [0, 0], max: [1, 2, 3]}\n"), "extent.max");
  ExpectInvalid(ParseWorldYaml("extent: {min: [0, 0], max: [1, 0]}\n"), "extent: max must exceed");
}

TEST(WorldDescriptionTest, NotAMapping) {
  ExpectInvalid(ParseWorldYaml("- 1\n- 2\n"), "world");
  ExpectInvalid(ParseWorldYaml("extent: {min: [0, 0], max: [1, 1]\n"), "world YAML");
}

TEST(WorldDescriptionTest, WallEndpointNamed) {
  ExpectInvalid(ParseWorldYaml(WithExtent("walls: [{from: [0, 0], to: [1]}]\n")),
                "walls[0].to: expected [x, y]");
  ExpectInvalid(ParseWorldYaml(WithExtent("walls: [{from: [0, 0]}]\n")), "walls[0].to");
  ExpectInvalid(ParseWorldYaml(WithExtent("walls: [{from: [0, 0], to: [1, 0]}, {to: [1, 0]}]\n")),
                "walls[1].from");
  ExpectInvalid(ParseWorldYaml(WithExtent("fences: [{from: [0, 0], to: [.nan, 0]}]\n")),
                "fences[0].to: not finite");
}

TEST(WorldDescriptionTest, ZeroLengthWall) {
  ExpectInvalid(ParseWorldYaml(WithExtent("walls: [{from: [1, 1], to: [1, 1]}]\n")),
                "walls[0]: from and to are the same point");
}

TEST(WorldDescriptionTest, NonPositiveThicknessAndHeight) {
  ExpectInvalid(ParseWorldYaml(WithExtent("walls: [{from: [0, 0], to: [1, 0], thickness: 0}]\n")),
                "walls[0].thickness: must be > 0");
  ExpectInvalid(
      ParseWorldYaml(WithExtent("fences: [{from: [0, 0], to: [1, 0], thickness: -0.1}]\n")),
      "fences[0].thickness: must be > 0");
  ExpectInvalid(ParseWorldYaml(WithExtent("walls: [{from: [0, 0], to: [1, 0], height: -1}]\n")),
                "walls[0].height: must be > 0");
}

TEST(WorldDescriptionTest, OtherEntriesNamed) {
  ExpectInvalid(ParseWorldYaml(WithExtent("boxes: [{center: [0, 0], size: [1, 0]}]\n")),
                "boxes[0].size: must be > 0");
  ExpectInvalid(ParseWorldYaml(WithExtent("boxes: [{size: [1, 1]}]\n")), "boxes[0].center");
  ExpectInvalid(ParseWorldYaml(WithExtent("cylinders: [{center: [0, 0], radius: 0}]\n")),
                "cylinders[0].radius: must be > 0");
  ExpectInvalid(ParseWorldYaml(WithExtent("stripes: [{id: 1, points: [[0, 0]]}]\n")),
                "stripes[0].points: needs at least 2 points");
  ExpectInvalid(ParseWorldYaml(WithExtent("markers: [{id: 1, at: [0]}]\n")), "markers[0].at");
  ExpectInvalid(ParseWorldYaml(WithExtent("robots: [{id: r, kind: lely-vector, pose: [0, 0]}]\n")),
                "robots[0].pose: expected [x, y, yaw_deg]");
}

}  // namespace
}  // namespace fleetnav::sim
