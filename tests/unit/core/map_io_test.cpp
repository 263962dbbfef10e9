#include "fleetnav/core/map_io.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "fleetnav/core/angles.hpp"

namespace fleetnav {
namespace {

using ::testing::HasSubstr;

template <typename T>
void ExpectInvalid(const absl::StatusOr<T>& result, const std::string& needle) {
  ASSERT_FALSE(result.ok()) << "expected an error containing '" << needle << "'";
  EXPECT_EQ(result.status().code(), absl::StatusCode::kInvalidArgument) << result.status();
  EXPECT_THAT(std::string(result.status().message()), HasSubstr(needle));
}

std::filesystem::path UniqueTempDir(const std::string& name) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) /
                              ("fleetnav_map_io_" + std::string(info->name()) + "_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

std::string ReadAll(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

constexpr char kYaml[] = R"(image: barn.pgm
resolution: 0.05
origin: [-12.5, -3.0, 0.0]
negate: 0
occupied_thresh: 0.65
free_thresh: 0.196
)";

// --- YAML ---------------------------------------------------------------------------------

TEST(MapServerYamlTest, ParsesTheStandardFields) {
  absl::StatusOr<MapServerMetadata> metadata = ParseMapServerYaml(kYaml);
  ASSERT_TRUE(metadata.ok()) << metadata.status();
  EXPECT_EQ(metadata->image, "barn.pgm");
  EXPECT_DOUBLE_EQ(metadata->resolution_m, 0.05);
  EXPECT_DOUBLE_EQ(metadata->origin.x_m(), -12.5);
  EXPECT_DOUBLE_EQ(metadata->origin.y_m(), -3.0);
  EXPECT_FALSE(metadata->negate);
  EXPECT_DOUBLE_EQ(metadata->occupied_thresh, 0.65);
  EXPECT_DOUBLE_EQ(metadata->free_thresh, 0.196);
  EXPECT_EQ(metadata->mode, MapServerMode::kTrinary);
}

TEST(MapServerYamlTest, ParsesModeAndNegateSpellings) {
  absl::StatusOr<MapServerMetadata> scale = ParseMapServerYaml(
      "image: a.pgm\nresolution: 0.1\norigin: [0, 0, 0.5]\nnegate: true\nmode: scale\n");
  ASSERT_TRUE(scale.ok()) << scale.status();
  EXPECT_TRUE(scale->negate);
  EXPECT_EQ(scale->mode, MapServerMode::kScale);
  EXPECT_DOUBLE_EQ(scale->origin.yaw_rad(), 0.5);
  absl::StatusOr<MapServerMetadata> raw = ParseMapServerYaml(
      "image: a.pgm\nresolution: 0.1\norigin: [0, 0, 0]\nnegate: 1\nmode: raw\n");
  ASSERT_TRUE(raw.ok()) << raw.status();
  EXPECT_TRUE(raw->negate);
  EXPECT_EQ(raw->mode, MapServerMode::kRaw);
}

TEST(MapServerYamlTest, MissingRequiredKeysAreNamed) {
  ExpectInvalid(ParseMapServerYaml("resolution: 0.05\norigin: [0, 0, 0]\n"), "'image'");
  ExpectInvalid(ParseMapServerYaml("image: a.pgm\norigin: [0, 0, 0]\n"), "'resolution'");
  ExpectInvalid(ParseMapServerYaml("image: a.pgm\nresolution: 0.05\n"), "'origin'");
}

TEST(MapServerYamlTest, RejectsNegativeOrNanResolution) {
  ExpectInvalid(ParseMapServerYaml("image: a.pgm\nresolution: -0.05\norigin: [0, 0, 0]\n"),
                "resolution must be finite and > 0, got -0.05");
  ExpectInvalid(ParseMapServerYaml("image: a.pgm\nresolution: .nan\norigin: [0, 0, 0]\n"),
                "resolution must be finite and > 0, got nan");
  ExpectInvalid(ParseMapServerYaml("image: a.pgm\nresolution: fine\norigin: [0, 0, 0]\n"),
                "resolution: expected a number, got 'fine'");
}

TEST(MapServerYamlTest, RejectsBadValues) {
  ExpectInvalid(ParseMapServerYaml("image: a.pgm\nresolution: 0.1\norigin: [0, 0]\n"), "origin");
  ExpectInvalid(
      ParseMapServerYaml("image: a.pgm\nresolution: 0.1\norigin: [0, 0, 0]\nmode: fancy\n"),
      "mode: unknown value 'fancy'");
  ExpectInvalid(
      ParseMapServerYaml("image: a.pgm\nresolution: 0.1\norigin: [0, 0, 0]\nnegate: maybe\n"),
      "negate");
  ExpectInvalid(
      ParseMapServerYaml("image: a.pgm\nresolution: 0.1\norigin: [0, 0, 0]\nfree_thresh: 0.8\n"),
      "free_thresh (0.8) must be below occupied_thresh (0.65)");
  ExpectInvalid(ParseMapServerYaml("image: [a\n"), "YAML syntax error");
  ExpectInvalid(ParseMapServerYaml("- just\n- a list\n"), "mapping");
}

TEST(MapServerYamlTest, WriteThenParseIsExact) {
  MapServerMetadata metadata;
  metadata.image = "my map.pgm";
  metadata.resolution_m = 0.025;
  metadata.origin = Pose2(-1.0 / 3.0, 7.125, 0.1);
  metadata.negate = true;
  metadata.mode = MapServerMode::kScale;
  metadata.occupied_thresh = 0.7;
  metadata.free_thresh = 0.1;
  absl::StatusOr<MapServerMetadata> parsed = ParseMapServerYaml(MapServerYamlToString(metadata));
  ASSERT_TRUE(parsed.ok()) << parsed.status();
  EXPECT_EQ(parsed->image, metadata.image);
  EXPECT_EQ(parsed->resolution_m, metadata.resolution_m);
  EXPECT_EQ(parsed->origin.x_m(), metadata.origin.x_m());
  EXPECT_EQ(parsed->origin.y_m(), metadata.origin.y_m());
  EXPECT_EQ(parsed->origin.yaw_rad(), metadata.origin.yaw_rad());
  EXPECT_TRUE(parsed->negate);
  EXPECT_EQ(parsed->mode, MapServerMode::kScale);
  EXPECT_EQ(parsed->occupied_thresh, 0.7);
  EXPECT_EQ(parsed->free_thresh, 0.1);
}

// --- PGM ----------------------------------------------------------------------------------

TEST(PgmTest, DecodesBinaryP5) {
  const std::string bytes =
      std::string("P5\n# made by hand\n3 2\n255\n") + std::string("\x00\x80\xff\x01\x02\x03", 6);
  absl::StatusOr<PgmImage> image = DecodePgm(bytes);
  ASSERT_TRUE(image.ok()) << image.status();
  EXPECT_EQ(image->width, 3);
  EXPECT_EQ(image->height, 2);
  EXPECT_EQ(image->max_value, 255);
  EXPECT_EQ(image->pixels, (std::vector<uint8_t>{0, 128, 255, 1, 2, 3}));
}

TEST(PgmTest, DecodesAsciiP2WithCommentsAndScalesMaxval) {
  absl::StatusOr<PgmImage> image =
      DecodePgm("P2 # comment after magic\n2 2 # size\n15\n0 15\n# row\n5 10\n");
  ASSERT_TRUE(image.ok()) << image.status();
  EXPECT_EQ(image->max_value, 15);
  EXPECT_EQ(image->pixels, (std::vector<uint8_t>{0, 255, 85, 170}));
}

TEST(PgmTest, EncodeThenDecodeIsExact) {
  PgmImage image;
  image.width = 17;
  image.height = 9;
  std::mt19937 rng(1);
  for (int i = 0; i < image.width * image.height; ++i) {
    image.pixels.push_back(static_cast<uint8_t>(rng() % 256));
  }
  const std::string bytes = EncodePgm(image);
  EXPECT_EQ(bytes.rfind("P5\n17 9\n255\n", 0), 0u);
  absl::StatusOr<PgmImage> decoded = DecodePgm(bytes);
  ASSERT_TRUE(decoded.ok()) << decoded.status();
  EXPECT_EQ(decoded->width, image.width);
  EXPECT_EQ(decoded->height, image.height);
  EXPECT_EQ(decoded->pixels, image.pixels);
}

TEST(PgmTest, RejectsTruncatedData) {
  ExpectInvalid(DecodePgm(std::string("P5\n4 4\n255\n") + std::string(10, '\x7f')),
                "PGM truncated: expected 16 bytes of raster data, got 10");
  ExpectInvalid(DecodePgm("P5\n4 4\n255"), "truncated");
  ExpectInvalid(DecodePgm("P2\n2 2\n255\n1 2 3\n"),
                "PGM truncated: expected 4 pixel values, got 3");
  ExpectInvalid(DecodePgm("P5\n4"), "PGM truncated: missing height");
  ExpectInvalid(DecodePgm(""), "magic");
}

TEST(PgmTest, RejectsWrongMagic) {
  ExpectInvalid(DecodePgm("P6\n1 1\n255\nabc"), "wrong magic 'P6'");
  ExpectInvalid(DecodePgm("GIF89a"), "wrong magic");
  ExpectInvalid(DecodePgm("# comment first\nP5\n1 1\n255\n\x01"), "wrong magic");
}

TEST(PgmTest, RejectsBadSizes) {
  ExpectInvalid(DecodePgm("P5\n-3 2\n255\n"), "PGM width must be > 0, got -3");
  ExpectInvalid(DecodePgm("P5\n3 0\n255\n"), "PGM height must be > 0, got 0");
  ExpectInvalid(DecodePgm("P5\n20000 20000\n255\n"), "exceeds the limit");
  ExpectInvalid(DecodePgm("P5\n99999999999999999999 1\n255\n"), "width is not an integer");
  ExpectInvalid(DecodePgm("P5\nthree 2\n255\n"), "width is not an integer: 'three'");
}

TEST(PgmTest, ReadsSixteenBitSamplesAndRejectsBadMaxval) {
  // Two samples of two bytes, most significant first: 0x0101 and 0xffff of 65535.
  const std::string p5("P5\n2 1\n65535\n\x01\x01\xff\xff", 17);
  absl::StatusOr<PgmImage> image = DecodePgm(p5);
  ASSERT_TRUE(image.ok()) << image.status();
  EXPECT_EQ(image->pixels, (std::vector<uint8_t>{1, 255}));
  absl::StatusOr<PgmImage> ascii = DecodePgm("P2\n2 1\n1000\n500 1000\n");
  ASSERT_TRUE(ascii.ok()) << ascii.status();
  EXPECT_EQ(ascii->pixels, (std::vector<uint8_t>{128, 255}));
  ExpectInvalid(DecodePgm(std::string("P5\n2 1\n65535\n\x01\x01\xff", 16)),
                "expected 4 bytes of raster data, got 3");
  ExpectInvalid(DecodePgm("P5\n1 1\n0\n\x00"), "maxval must be in [1, 65535], got 0");
  ExpectInvalid(DecodePgm("P5\n1 1\n65536\n\x00"), "maxval must be in [1, 65535], got 65536");
  ExpectInvalid(DecodePgm("P2\n1 1\n15\n16\n"), "PGM pixel 0 = '16' is not an integer in [0, 15]");
}

// --- map_server semantics ------------------------------------------------------------------

PgmImage OneRow(std::vector<uint8_t> pixels) {
  PgmImage image;
  image.width = static_cast<int>(pixels.size());
  image.height = 1;
  image.pixels = std::move(pixels);
  return image;
}

MapServerMetadata Metadata(MapServerMode mode, bool negate) {
  MapServerMetadata metadata;
  metadata.image = "x.pgm";
  metadata.mode = mode;
  metadata.negate = negate;
  return metadata;
}

TEST(GridFromMapServerTest, TrinaryThresholds) {
  // p = (255 - v) / 255: 0 -> 1.0, 89 -> 0.651, 90 -> 0.647, 205 -> 0.196, 206 -> 0.192.
  absl::StatusOr<OccupancyGrid> grid = GridFromMapServer(Metadata(MapServerMode::kTrinary, false),
                                                         OneRow({0, 89, 90, 205, 206, 254, 255}));
  ASSERT_TRUE(grid.ok()) << grid.status();
  EXPECT_EQ(grid->cells(), (std::vector<int8_t>{100, 100, -1, -1, 0, 0, 0}));
}

TEST(GridFromMapServerTest, NegateSwapsBlackAndWhite) {
  absl::StatusOr<OccupancyGrid> grid =
      GridFromMapServer(Metadata(MapServerMode::kTrinary, true), OneRow({0, 255, 128}));
  ASSERT_TRUE(grid.ok()) << grid.status();
  EXPECT_EQ(grid->cells(), (std::vector<int8_t>{0, 100, -1}));
}

TEST(GridFromMapServerTest, ScaleInterpolatesBetweenThresholds) {
  // v = 128: p = 127/255 = 0.498; 99 * (0.498 - 0.196) / (0.65 - 0.196) = 65.9 -> 66.
  absl::StatusOr<OccupancyGrid> grid =
      GridFromMapServer(Metadata(MapServerMode::kScale, false), OneRow({0, 128, 255, 200}));
  ASSERT_TRUE(grid.ok()) << grid.status();
  EXPECT_EQ(grid->cells()[0], 100);
  EXPECT_EQ(grid->cells()[1], 66);
  EXPECT_EQ(grid->cells()[2], 0);
  // v = 200: p = 0.2157 -> 99 * 0.0196 / 0.454 = 4.3 -> 4.
  EXPECT_EQ(grid->cells()[3], 4);
}

TEST(GridFromMapServerTest, RawUsesValuesDirectly) {
  absl::StatusOr<OccupancyGrid> grid =
      GridFromMapServer(Metadata(MapServerMode::kRaw, false), OneRow({0, 42, 100, 101, 255}));
  ASSERT_TRUE(grid.ok()) << grid.status();
  EXPECT_EQ(grid->cells(), (std::vector<int8_t>{0, 42, 100, -1, -1}));
}

TEST(GridFromMapServerTest, TopImageRowIsTopGridRow) {
  PgmImage image;
  image.width = 2;
  image.height = 3;
  image.pixels = {0, 0, 254, 254, 205, 205};  // top row occupied, bottom row unknown
  absl::StatusOr<OccupancyGrid> grid =
      GridFromMapServer(Metadata(MapServerMode::kTrinary, false), image);
  ASSERT_TRUE(grid.ok()) << grid.status();
  EXPECT_EQ(grid->Value({0, 2}), 100);
  EXPECT_EQ(grid->Value({1, 1}), 0);
  EXPECT_EQ(grid->Value({0, 0}), -1);
}

TEST(GridFromMapServerTest, RejectsPixelCountMismatch) {
  PgmImage image = OneRow({0, 0, 0});
  image.width = 4;
  ExpectInvalid(GridFromMapServer(Metadata(MapServerMode::kTrinary, false), image),
                "image has 3 pixels, expected width*height = 4");
}

OccupancyGrid RandomTrinaryGrid(int width, int height, const Pose2& origin, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<int8_t> cells;
  const int8_t values[] = {0, 100, -1};
  for (int i = 0; i < width * height; ++i) cells.push_back(values[rng() % 3]);
  absl::StatusOr<OccupancyGrid> grid = OccupancyGrid::Create(width, height, 0.05, origin, cells);
  EXPECT_TRUE(grid.ok());
  return *std::move(grid);
}

TEST(MapServerRoundTripTest, InMemoryRoundTripIsExact) {
  const OccupancyGrid grid = RandomTrinaryGrid(31, 17, Pose2(-4.2, 1.3, 0.25), 99);
  const auto [metadata, image] = GridToMapServer(grid, "round.pgm");
  EXPECT_EQ(metadata.image, "round.pgm");
  EXPECT_EQ(metadata.mode, MapServerMode::kTrinary);
  EXPECT_DOUBLE_EQ(metadata.occupied_thresh, 0.65);
  EXPECT_DOUBLE_EQ(metadata.free_thresh, 0.196);
  for (uint8_t pixel : image.pixels) EXPECT_TRUE(pixel == 254 || pixel == 0 || pixel == 205);
  absl::StatusOr<OccupancyGrid> back =
      GridFromMapServerBytes(MapServerYamlToString(metadata), EncodePgm(image));
  ASSERT_TRUE(back.ok()) << back.status();
  EXPECT_TRUE(*back == grid);
}

// A grid read in scale mode holds values between free and occupied: it is written in raw mode
// (the value as the pixel), which reads back exactly; trinary would keep only the states.
TEST(MapServerRoundTripTest, IntermediateValuesAreWrittenRawAndReadBackExactly) {
  absl::StatusOr<OccupancyGrid> grid =
      OccupancyGrid::Create(5, 1, 0.1, Pose2(), {0, 10, 40, 100, -1});
  ASSERT_TRUE(grid.ok());
  const auto [metadata, image] = GridToMapServer(*grid, "x.pgm");
  EXPECT_EQ(metadata.mode, MapServerMode::kRaw);
  EXPECT_EQ(image.pixels, (std::vector<uint8_t>{0, 10, 40, 100, 255}));
  absl::StatusOr<OccupancyGrid> back =
      GridFromMapServerBytes(MapServerYamlToString(metadata), EncodePgm(image));
  ASSERT_TRUE(back.ok()) << back.status();
  EXPECT_TRUE(*back == *grid);
}

TEST(MapServerRoundTripTest, SaveThenLoadIsExact) {
  const std::filesystem::path dir = UniqueTempDir("save");
  const OccupancyGrid grid = RandomTrinaryGrid(40, 25, Pose2(2.0, -3.5, -0.4), 7);
  const std::string yaml_path = (dir / "barn.yaml").string();
  ASSERT_TRUE(SaveMapServer(grid, yaml_path).ok());
  ASSERT_TRUE(std::filesystem::exists(dir / "barn.pgm"));
  // The YAML names the image relative to its own folder.
  EXPECT_THAT(ReadAll(yaml_path), HasSubstr("image: barn.pgm\n"));
  EXPECT_EQ(ReadAll(dir / "barn.pgm").rfind("P5\n40 25\n255\n", 0), 0u);
  absl::StatusOr<OccupancyGrid> loaded = LoadMapServer(yaml_path);
  ASSERT_TRUE(loaded.ok()) << loaded.status();
  EXPECT_TRUE(*loaded == grid);
}

TEST(MapServerRoundTripTest, SaveRequiresYamlSuffix) {
  const OccupancyGrid grid = RandomTrinaryGrid(2, 2, Pose2(), 1);
  const absl::Status status = SaveMapServer(grid, (UniqueTempDir("suffix") / "map.txt").string());
  EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(status.message()), HasSubstr(".yaml"));
}

TEST(LoadMapServerTest, LoadsHandWrittenP2File) {
  absl::StatusOr<OccupancyGrid> grid =
      LoadMapServer(std::string(FLEETNAV_TEST_DATA_DIR) + "/maps/tiny_p2.yaml");
  ASSERT_TRUE(grid.ok()) << grid.status();
  EXPECT_EQ(grid->width(), 4);
  EXPECT_EQ(grid->height(), 3);
  EXPECT_DOUBLE_EQ(grid->resolution_m(), 0.5);
  EXPECT_DOUBLE_EQ(grid->origin().x_m(), -1.0);
  EXPECT_DOUBLE_EQ(grid->origin().y_m(), 2.0);
  // Image rows top to bottom: [0 15 12 15], [15 15 15 15], [15 0 0 15] with maxval 15.
  EXPECT_EQ(grid->cells(), (std::vector<int8_t>{0, 100, 100, 0, 0, 0, 0, 0, 100, 0, -1, 0}));
  EXPECT_EQ(grid->StateAtWorld({-0.75, 3.25}), CellState::kOccupied);  // cell (0, 2)
}

TEST(LoadMapServerTest, KeepsAbsoluteImagePath) {
  const std::filesystem::path dir = UniqueTempDir("absolute");
  const OccupancyGrid grid = RandomTrinaryGrid(5, 4, Pose2(), 3);
  ASSERT_TRUE(SaveMapServer(grid, (dir / "a.yaml").string()).ok());
  std::filesystem::create_directories(dir / "elsewhere");
  {
    std::ofstream yaml(dir / "elsewhere" / "b.yaml");
    yaml << "image: " << (dir / "a.pgm").string() << "\nresolution: 0.05\norigin: [0, 0, 0]\n";
  }
  absl::StatusOr<OccupancyGrid> loaded = LoadMapServer((dir / "elsewhere" / "b.yaml").string());
  ASSERT_TRUE(loaded.ok()) << loaded.status();
  EXPECT_TRUE(*loaded == grid);
}

TEST(LoadMapServerTest, MissingFilesAreNotFound) {
  const std::filesystem::path dir = UniqueTempDir("missing");
  EXPECT_EQ(LoadMapServer((dir / "none.yaml").string()).status().code(),
            absl::StatusCode::kNotFound);
  {
    std::ofstream yaml(dir / "lonely.yaml");
    yaml << "image: gone.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n";
  }
  const absl::Status status = LoadMapServer((dir / "lonely.yaml").string()).status();
  EXPECT_EQ(status.code(), absl::StatusCode::kNotFound);
  EXPECT_THAT(std::string(status.message()), HasSubstr("gone.pgm"));
}

TEST(LoadMapServerTest, BadImageIsReportedWithItsPath) {
  const std::filesystem::path dir = UniqueTempDir("bad_image");
  {
    std::ofstream yaml(dir / "m.yaml");
    yaml << "image: m.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n";
    std::ofstream pgm(dir / "m.pgm", std::ios::binary);
    pgm << "P5\n10 10\n255\nshort";
  }
  const absl::Status status = LoadMapServer((dir / "m.yaml").string()).status();
  EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(status.message()), HasSubstr("m.pgm"));
  EXPECT_THAT(std::string(status.message()), HasSubstr("truncated"));
}

}  // namespace
}  // namespace fleetnav
