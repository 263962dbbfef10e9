#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/stripe_marker.hpp"

namespace fleetnav {
namespace {

using ::testing::HasSubstr;

void ExpectInvalid(const absl::StatusOr<MarkerSet>& result, const std::string& needle) {
  ASSERT_FALSE(result.ok()) << "expected an error containing '" << needle << "'";
  EXPECT_EQ(result.status().code(), absl::StatusCode::kInvalidArgument) << result.status();
  EXPECT_THAT(std::string(result.status().message()), HasSubstr(needle));
}

// Two markers are the same when everything matches to 1e-9 and the yaws give the same line.
void ExpectSameMarkers(const MarkerSet& actual, const MarkerSet& expected) {
  EXPECT_EQ(actual.map_id, expected.map_id);
  ASSERT_EQ(actual.markers.size(), expected.markers.size());
  for (size_t i = 0; i < actual.markers.size(); ++i) {
    const StripeMarker& a = actual.markers[i];
    const StripeMarker& e = expected.markers[i];
    EXPECT_EQ(a.id, e.id);
    EXPECT_NEAR((a.position_m - e.position_m).norm(), 0.0, 1e-9);
    EXPECT_NEAR(a.z_m, e.z_m, 1e-9);
    EXPECT_NEAR(std::sin(a.yaw_rad - e.yaw_rad), 0.0, 1e-9) << "marker " << i;
    EXPECT_NEAR(a.length_m, e.length_m, 1e-9);
    EXPECT_EQ(a.kind, e.kind);
  }
}

// The two calibration markers of the thesis's SAMCL experiment (§7, markers at (0, 4.7) and
// (5, 4.7)), written in the thesis's form (eq. 5.5).
constexpr char kThesisMarkers[] = R"(map: test-barn
markers:
  - id: 1
    position: {x: 0.0, y: 4.7, z: 0.0}
    orientation: {a: 0.0, b: 0.0, c: 0.7071068, d: 0.7071068}
  - id: 2
    position: {x: 5.0, y: 4.7, z: 0.0}
    orientation: {a: 0.0, b: 0.0, c: 0.7071068, d: 0.7071068}
    length: 0.8
    kind: follow_stripe
)";

TEST(MarkerYamlTest, ParsesThesisForm) {
  absl::StatusOr<MarkerSet> set = ParseMarkerSetYaml(kThesisMarkers);
  ASSERT_TRUE(set.ok()) << set.status();
  EXPECT_EQ(set->map_id, "test-barn");
  ASSERT_EQ(set->markers.size(), 2u);
  EXPECT_EQ(set->markers[0].id, 1);
  EXPECT_NEAR(set->markers[0].position_m.y(), 4.7, 1e-12);
  EXPECT_NEAR(set->markers[0].yaw_rad, -kPi / 2.0, 1e-6);
  EXPECT_DOUBLE_EQ(set->markers[0].length_m, 0.5);
  EXPECT_EQ(set->markers[0].kind, MarkerKind::kCalibration);
  EXPECT_DOUBLE_EQ(set->markers[1].length_m, 0.8);
  EXPECT_EQ(set->markers[1].kind, MarkerKind::kFollowStripe);
}

TEST(MarkerYamlTest, MapKeyIsOptional) {
  absl::StatusOr<MarkerSet> set = ParseMarkerSetYaml(
      "markers:\n  - id: 3\n    position: {x: 1, y: 2}\n    orientation: {a: 0, b: 0, c: 0, "
      "d: 1}\n");
  ASSERT_TRUE(set.ok()) << set.status();
  EXPECT_TRUE(set->map_id.empty());
  EXPECT_DOUBLE_EQ(set->markers[0].z_m, 0.0);
  absl::StatusOr<MarkerSet> empty = ParseMarkerSetYaml("markers: []\n");
  ASSERT_TRUE(empty.ok()) << empty.status();
  EXPECT_TRUE(empty->markers.empty());
}

TEST(MarkerYamlTest, RejectsQuaternionNotOfUnitLengthNamingTheMarker) {
  ExpectInvalid(ParseMarkerSetYaml(R"(markers:
  - id: 1
    position: {x: 0, y: 0}
    orientation: {a: 0, b: 0, c: 0, d: 1}
  - id: 2
    position: {x: 0, y: 0}
    orientation: {a: 0, b: 0, c: 0, d: 1}
  - id: 3
    position: {x: 0, y: 0}
    orientation: {a: 0, b: 0, c: 0, d: 1}
  - id: 4
    position: {x: 1, y: 1}
    orientation: {a: 0, b: 0, c: 0, d: 1.2}
)"),
                "markers[3].orientation: quaternion not of unit length (|q| = 1.2)");
}

TEST(MarkerYamlTest, RejectsTiltedMarker) {
  ExpectInvalid(ParseMarkerSetYaml("markers:\n  - id: 1\n    position: {x: 0, y: 0}\n"
                                   "    orientation: {a: 0.2, b: 0, c: 0, d: 0.9798}\n"),
                "markers[0].orientation: quaternion tilts the marker out of the floor plane");
}

TEST(MarkerYamlTest, RejectsUnknownKeys) {
  ExpectInvalid(ParseMarkerSetYaml("markers:\n  - id: 1\n    position: {x: 0, y: 0}\n"
                                   "    orientation: {a: 0, b: 0, c: 0, d: 1}\n"
                                   "    colour: red\n"),
                "markers[0]: unknown key 'colour'");
  ExpectInvalid(ParseMarkerSetYaml("markers:\n  - id: 1\n    position: {x: 0, y: 0, w: 1}\n"
                                   "    orientation: {a: 0, b: 0, c: 0, d: 1}\n"),
                "markers[0].position: unknown key 'w'");
  ExpectInvalid(ParseMarkerSetYaml("markers: []\nstripes: []\n"), "unknown key 'stripes'");
}

TEST(MarkerYamlTest, RejectsMissingAndMalformedFields) {
  ExpectInvalid(ParseMarkerSetYaml("map: barn\n"), "missing 'markers'");
  ExpectInvalid(ParseMarkerSetYaml("markers:\n  - position: {x: 0, y: 0}\n"
                                   "    orientation: {a: 0, b: 0, c: 0, d: 1}\n"),
                "markers[0]: missing 'id'");
  ExpectInvalid(ParseMarkerSetYaml("markers:\n  - id: 1\n    position: {x: 0, y: 0}\n"),
                "markers[0]: missing 'orientation'");
  ExpectInvalid(ParseMarkerSetYaml("markers:\n  - id: 1\n    position: {x: zero, y: 0}\n"
                                   "    orientation: {a: 0, b: 0, c: 0, d: 1}\n"),
                "markers[0].position.x: expected a number, got 'zero'");
  ExpectInvalid(ParseMarkerSetYaml("markers:\n  - id: 1.5\n    position: {x: 0, y: 0}\n"
                                   "    orientation: {a: 0, b: 0, c: 0, d: 1}\n"),
                "markers[0].id: expected an integer");
  ExpectInvalid(ParseMarkerSetYaml("markers:\n  - id: 1\n    position: {x: 0, y: 0}\n"
                                   "    orientation: {a: 0, b: 0, c: 0, d: 1}\n"
                                   "    kind: sticker\n"),
                "markers[0].kind: unknown marker kind 'sticker'");
  ExpectInvalid(ParseMarkerSetYaml("markers: {x: 1}\n"), "markers: expected a list");
  ExpectInvalid(ParseMarkerSetYaml("markers: [\n"), "YAML syntax error");
}

TEST(MarkerYamlTest, RejectsDuplicateIds) {
  ExpectInvalid(ParseMarkerSetYaml("markers:\n"
                                   "  - {id: 7, position: {x: 0, y: 0}, orientation: {a: 0, b: 0, "
                                   "c: 0, d: 1}}\n"
                                   "  - {id: 7, position: {x: 1, y: 0}, orientation: {a: 0, b: 0, "
                                   "c: 0, d: 1}}\n"),
                "markers[1]: duplicate id 7");
}

MarkerSet RandomMarkers(uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> xy(-30.0, 30.0);
  std::uniform_real_distribution<double> yaw(-kPi / 2.0, kPi / 2.0);
  std::uniform_real_distribution<double> length(0.1, 2.0);
  MarkerSet set;
  set.map_id = "barn: north";  // needs quoting in YAML
  for (int i = 0; i < 50; ++i) {
    StripeMarker marker;
    marker.id = i * 3 - 20;
    marker.position_m = {xy(rng), xy(rng)};
    marker.yaw_rad = yaw(rng);
    marker.length_m = length(rng);
    marker.kind = static_cast<MarkerKind>(i % 3);
    set.markers.push_back(marker);
  }
  StripeMarker edge;  // the lower end of the yaw range
  edge.id = 1000;
  edge.yaw_rad = -kPi / 2.0;
  set.markers.push_back(edge);
  return set;
}

TEST(MarkerYamlTest, RoundTrip) {
  const MarkerSet original = RandomMarkers(17);
  const std::string yaml = MarkerSetToYaml(original);
  absl::StatusOr<MarkerSet> parsed = ParseMarkerSetYaml(yaml);
  ASSERT_TRUE(parsed.ok()) << parsed.status() << "\n" << yaml;
  ExpectSameMarkers(*parsed, original);
  // A second round trip stays put too (the yaw goes through a quaternion, so allow 1e-9).
  absl::StatusOr<MarkerSet> twice = ParseMarkerSetYaml(MarkerSetToYaml(*parsed));
  ASSERT_TRUE(twice.ok()) << twice.status();
  ExpectSameMarkers(*twice, original);
}

TEST(MarkerFileTest, SaveThenLoad) {
  const std::filesystem::path path =
      std::filesystem::path(::testing::TempDir()) / "fleetnav_marker_io_save_then_load.yaml";
  const MarkerSet original = RandomMarkers(3);
  ASSERT_TRUE(SaveMarkerSet(original, path.string()).ok());
  absl::StatusOr<MarkerSet> loaded = LoadMarkerSet(path.string());
  ASSERT_TRUE(loaded.ok()) << loaded.status();
  ExpectSameMarkers(*loaded, original);
  std::filesystem::remove(path);
}

TEST(MarkerFileTest, SaveRefusesInvalidSetAndLoadReportsMissingFile) {
  MarkerSet invalid = RandomMarkers(5);
  invalid.markers[2].id = invalid.markers[1].id;
  const std::filesystem::path path =
      std::filesystem::path(::testing::TempDir()) / "fleetnav_marker_io_invalid.yaml";
  EXPECT_EQ(SaveMarkerSet(invalid, path.string()).code(), absl::StatusCode::kInvalidArgument);
  EXPECT_FALSE(std::filesystem::exists(path));
  EXPECT_EQ(LoadMarkerSet(path.string()).status().code(), absl::StatusCode::kNotFound);
}

TEST(MarkerYamlTest, TrolleysRoundTripAndDuplicateIdsAreRefused) {
  absl::StatusOr<MarkerSet> set = ParseMarkerSetYaml(
      "map: store\nmarkers: []\ntrolleys:\n"
      "  - {id: t1, pose: [1.5, -2.0, 90], size: [1.0, 0.7], leg_radius: 0.025}\n"
      "  - {id: t2, pose: [4, 0, 0]}\n");
  ASSERT_TRUE(set.ok()) << set.status();
  ASSERT_EQ(set->trolleys.size(), 2u);
  EXPECT_EQ(set->trolleys[0].id, "t1");
  EXPECT_NEAR(set->trolleys[0].pose.yaw_rad(), (kPi / 2), 1e-12);
  EXPECT_NEAR(set->trolleys[0].leg_radius_m, 0.025, 1e-12);
  EXPECT_NEAR(set->trolleys[1].size_m.x(), 1.0, 1e-12);  // the default size
  ASSERT_NE(set->FindTrolley("t2"), nullptr);
  EXPECT_EQ(set->FindTrolley("t3"), nullptr);
  absl::StatusOr<MarkerSet> back = ParseMarkerSetYaml(MarkerSetToYaml(*set));
  ASSERT_TRUE(back.ok()) << back.status();
  ASSERT_EQ(back->trolleys.size(), 2u);
  EXPECT_NEAR(back->trolleys[0].pose.x_m(), 1.5, 1e-9);
  EXPECT_NEAR(back->trolleys[0].pose.yaw_rad(), (kPi / 2), 1e-9);
  const absl::Status duplicate = ParseMarkerSetYaml(
                                     "markers: []\ntrolleys:\n  - {id: t1, pose: [0, 0, 0]}\n"
                                     "  - {id: t1, pose: [3, 0, 0]}\n")
                                     .status();
  EXPECT_EQ(duplicate.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(duplicate.message()), ::testing::HasSubstr("trolleys[1]"));
}

}  // namespace
}  // namespace fleetnav
