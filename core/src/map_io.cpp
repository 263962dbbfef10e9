#include "fleetnav/core/map_io.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>
#include <utility>

#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "fleetnav/core/map_image.hpp"
#include "fleetnav/core/status_macros.hpp"
#include "io_internal.hpp"

namespace fleetnav {
namespace {

using internal::AsDouble;
using internal::FormatDouble;

// Pixel values written by GridToMapServer (the map_saver convention).
constexpr uint8_t kFreePixel = 254;
constexpr uint8_t kOccupiedPixel = 0;
constexpr uint8_t kUnknownPixel = 205;
// Raw mode: the pixel is the cell value; above 100 is unknown.
constexpr uint8_t kRawUnknownPixel = 255;
constexpr int kMaxPgmValue = 255;
constexpr int kMaxPgm16Value = 65535;

// ---------------------------------------------------------------------------------------------
// YAML

absl::StatusOr<MapServerMode> ParseMode(const std::string& name) {
  if (name == "trinary") return MapServerMode::kTrinary;
  if (name == "scale") return MapServerMode::kScale;
  if (name == "raw") return MapServerMode::kRaw;
  return absl::InvalidArgumentError(
      absl::StrCat("mode: unknown value '", name, "' (expected trinary, scale or raw)"));
}

absl::string_view ModeName(MapServerMode mode) {
  switch (mode) {
    case MapServerMode::kTrinary:
      return "trinary";
    case MapServerMode::kScale:
      return "scale";
    case MapServerMode::kRaw:
      return "raw";
  }
  return "trinary";
}

absl::StatusOr<YAML::Node> RequiredKey(const YAML::Node& root, const char* key) {
  YAML::Node node = root[key];
  if (!node.IsDefined() || node.IsNull()) {
    return absl::InvalidArgumentError(absl::StrCat("map YAML: missing required key '", key, "'"));
  }
  return node;
}

absl::StatusOr<Pose2> ParseOrigin(const YAML::Node& node) {
  if (!node.IsSequence() || node.size() != 3) {
    return absl::InvalidArgumentError(
        absl::StrCat("origin: expected [x, y, yaw], got ", internal::NodeText(node)));
  }
  ASSIGN_OR_RETURN(const double x_m, AsDouble(node[0], "origin[0]"));
  ASSIGN_OR_RETURN(const double y_m, AsDouble(node[1], "origin[1]"));
  ASSIGN_OR_RETURN(const double yaw_rad, AsDouble(node[2], "origin[2]"));
  const Pose2 origin(x_m, y_m, yaw_rad);
  if (!origin.IsFinite()) return absl::InvalidArgumentError("origin: values must be finite");
  return origin;
}

// `negate` is written 0/1 by map_saver and true/false by hand.
absl::StatusOr<bool> ParseNegate(const YAML::Node& node) {
  if (node.IsScalar()) {
    const std::string& text = node.Scalar();
    if (text == "0") return false;
    if (text == "1") return true;
    try {
      return node.as<bool>();
    } catch (const YAML::Exception&) {
    }
  }
  return absl::InvalidArgumentError(
      absl::StrCat("negate: expected 0, 1, true or false, got '", internal::NodeText(node), "'"));
}

absl::Status ValidateMetadata(const MapServerMetadata& metadata) {
  if (!std::isfinite(metadata.resolution_m) || metadata.resolution_m <= 0.0) {
    return absl::InvalidArgumentError(
        absl::StrFormat("resolution must be finite and > 0, got %g", metadata.resolution_m));
  }
  const auto in_unit_range = [](double v) { return std::isfinite(v) && v >= 0.0 && v <= 1.0; };
  if (!in_unit_range(metadata.occupied_thresh)) {
    return absl::InvalidArgumentError(
        absl::StrFormat("occupied_thresh must be in [0, 1], got %g", metadata.occupied_thresh));
  }
  if (!in_unit_range(metadata.free_thresh)) {
    return absl::InvalidArgumentError(
        absl::StrFormat("free_thresh must be in [0, 1], got %g", metadata.free_thresh));
  }
  if (metadata.free_thresh >= metadata.occupied_thresh) {
    return absl::InvalidArgumentError(
        absl::StrFormat("free_thresh (%g) must be below occupied_thresh (%g)", metadata.free_thresh,
                        metadata.occupied_thresh));
  }
  return absl::OkStatus();
}

absl::StatusOr<MapServerMetadata> MetadataFromNode(const YAML::Node& root) {
  if (!root.IsMap()) return absl::InvalidArgumentError("map YAML: expected a mapping at the top");
  ASSIGN_OR_RETURN(const YAML::Node image, RequiredKey(root, "image"));
  ASSIGN_OR_RETURN(const YAML::Node resolution, RequiredKey(root, "resolution"));
  ASSIGN_OR_RETURN(const YAML::Node origin, RequiredKey(root, "origin"));

  MapServerMetadata metadata;
  ASSIGN_OR_RETURN(metadata.image, internal::AsString(image, "image"));
  if (metadata.image.empty()) return absl::InvalidArgumentError("image: must not be empty");
  ASSIGN_OR_RETURN(metadata.resolution_m, AsDouble(resolution, "resolution"));
  ASSIGN_OR_RETURN(metadata.origin, ParseOrigin(origin));
  // negate and the thresholds are required by ROS 1 map_server; we accept their usual values
  // as defaults so that hand-written files stay short.
  if (const YAML::Node node = root["negate"]; node.IsDefined()) {
    ASSIGN_OR_RETURN(metadata.negate, ParseNegate(node));
  }
  if (const YAML::Node node = root["occupied_thresh"]; node.IsDefined()) {
    ASSIGN_OR_RETURN(metadata.occupied_thresh, AsDouble(node, "occupied_thresh"));
  }
  if (const YAML::Node node = root["free_thresh"]; node.IsDefined()) {
    ASSIGN_OR_RETURN(metadata.free_thresh, AsDouble(node, "free_thresh"));
  }
  if (const YAML::Node node = root["mode"]; node.IsDefined()) {
    ASSIGN_OR_RETURN(const std::string mode, internal::AsString(node, "mode"));
    ASSIGN_OR_RETURN(metadata.mode, ParseMode(mode));
  }
  RETURN_IF_ERROR(ValidateMetadata(metadata));
  return metadata;
}

// ---------------------------------------------------------------------------------------------
// PGM

// Reads the whitespace- and comment-separated tokens of a PGM header.
class PgmReader {
 public:
  explicit PgmReader(std::string_view bytes) : bytes_(bytes) {}

  // The next token, skipping whitespace and '#' comments; empty at the end of the data.
  std::string_view NextToken() {
    SkipSpaceAndComments();
    const size_t start = pos_;
    while (pos_ < bytes_.size() && !IsSpace(bytes_[pos_]) && bytes_[pos_] != '#') ++pos_;
    return bytes_.substr(start, pos_ - start);
  }

  absl::StatusOr<int64_t> NextInteger(absl::string_view field) {
    const absl::string_view token = internal::ToAbsl(NextToken());
    if (token.empty()) {
      return absl::InvalidArgumentError(absl::StrCat("PGM truncated: missing ", field));
    }
    int64_t value = 0;
    if (!absl::SimpleAtoi(token, &value)) {
      return absl::InvalidArgumentError(
          absl::StrCat("PGM: ", field, " is not an integer: '", token, "'"));
    }
    return value;
  }

  // P5: exactly one whitespace byte separates the header from the raster.
  bool SkipSingleSpace() {
    if (pos_ >= bytes_.size() || !IsSpace(bytes_[pos_])) return false;
    ++pos_;
    return true;
  }

  std::string_view Rest() const { return bytes_.substr(pos_); }

 private:
  static bool IsSpace(char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; }

  void SkipSpaceAndComments() {
    while (pos_ < bytes_.size()) {
      if (IsSpace(bytes_[pos_])) {
        ++pos_;
      } else if (bytes_[pos_] == '#') {
        while (pos_ < bytes_.size() && bytes_[pos_] != '\n' && bytes_[pos_] != '\r') ++pos_;
      } else {
        break;
      }
    }
  }

  std::string_view bytes_;
  size_t pos_ = 0;
};

absl::Status CheckPgmSize(int64_t width, int64_t height) {
  if (width <= 0)
    return absl::InvalidArgumentError(absl::StrCat("PGM width must be > 0, got ", width));
  if (height <= 0) {
    return absl::InvalidArgumentError(absl::StrCat("PGM height must be > 0, got ", height));
  }
  if (width > kMaxGridCells || height > kMaxGridCells || width * height > kMaxGridCells) {
    return absl::InvalidArgumentError(absl::StrCat(
        "PGM of ", width, " x ", height, " pixels exceeds the limit of ", kMaxGridCells, " cells"));
  }
  return absl::OkStatus();
}

absl::Status CheckMaxValue(int64_t max_value) {
  if (max_value <= 0 || max_value > kMaxPgm16Value) {
    return absl::InvalidArgumentError(
        absl::StrCat("PGM maxval must be in [1, 65535], got ", max_value));
  }
  return absl::OkStatus();
}

uint8_t ScaleTo255(int64_t value, int64_t max_value) {
  return static_cast<uint8_t>((value * kMaxPgmValue + max_value / 2) / max_value);
}

absl::Status ReadBinaryRaster(PgmReader& reader, PgmImage& image) {
  if (!reader.SkipSingleSpace()) {
    return absl::InvalidArgumentError("PGM truncated: no raster data after the header");
  }
  const std::string_view raster = reader.Rest();
  const size_t expected = static_cast<size_t>(image.width) * image.height;
  // Above maxval 255 each sample is two bytes, most significant first (netpbm).
  const size_t bytes_per_sample = image.max_value > kMaxPgmValue ? 2 : 1;
  if (raster.size() < expected * bytes_per_sample) {
    return absl::InvalidArgumentError(absl::StrCat("PGM truncated: expected ",
                                                   expected * bytes_per_sample,
                                                   " bytes of raster data, got ", raster.size()));
  }
  image.pixels.resize(expected);
  for (size_t i = 0; i < expected; ++i) {
    const int64_t value = bytes_per_sample == 1 ? static_cast<unsigned char>(raster[i])
                                                : static_cast<unsigned char>(raster[2 * i]) * 256 +
                                                      static_cast<unsigned char>(raster[2 * i + 1]);
    if (value > image.max_value) {
      return absl::InvalidArgumentError(
          absl::StrCat("PGM pixel ", i, " = ", value, " exceeds maxval ", image.max_value));
    }
    image.pixels[i] = ScaleTo255(value, image.max_value);
  }
  return absl::OkStatus();
}

absl::Status ReadAsciiRaster(PgmReader& reader, PgmImage& image) {
  const size_t expected = static_cast<size_t>(image.width) * image.height;
  image.pixels.resize(expected);
  for (size_t i = 0; i < expected; ++i) {
    const absl::string_view token = internal::ToAbsl(reader.NextToken());
    if (token.empty()) {
      return absl::InvalidArgumentError(
          absl::StrCat("PGM truncated: expected ", expected, " pixel values, got ", i));
    }
    int64_t value = 0;
    if (!absl::SimpleAtoi(token, &value) || value < 0 || value > image.max_value) {
      return absl::InvalidArgumentError(absl::StrCat(
          "PGM pixel ", i, " = '", token, "' is not an integer in [0, ", image.max_value, "]"));
    }
    image.pixels[i] = ScaleTo255(value, image.max_value);
  }
  return absl::OkStatus();
}

// ---------------------------------------------------------------------------------------------
// Pixel interpretation (ROS map_server)

absl::StatusOr<int8_t> CellValueFromPixel(uint8_t pixel, bool transparent,
                                          const MapServerMetadata& metadata) {
  // The "lightness" after negate; map_server's occupancy probability is p = (255 - v) / 255.
  const int value = metadata.negate ? kMaxPgmValue - pixel : pixel;
  if (metadata.mode == MapServerMode::kRaw) {
    // Raw values are occupancy percentages; anything above 100 is unknown (as in nav2).
    return static_cast<int8_t>(
        value <= OccupancyGrid::kOccupiedValue ? value : OccupancyGrid::kUnknownValue);
  }
  const double p = static_cast<double>(kMaxPgmValue - value) / kMaxPgmValue;
  if (p > metadata.occupied_thresh) return OccupancyGrid::kOccupiedValue;
  if (p < metadata.free_thresh) return OccupancyGrid::kFreeValue;
  // map_server: between the thresholds a transparent pixel is unknown in scale mode too.
  if (metadata.mode == MapServerMode::kTrinary || transparent) return OccupancyGrid::kUnknownValue;
  const double ratio =
      (p - metadata.free_thresh) / (metadata.occupied_thresh - metadata.free_thresh);
  return static_cast<int8_t>(std::lround(99.0 * ratio));
}

uint8_t PixelFromCellValue(const OccupancyGrid& grid, CellIndex cell, MapServerMode mode) {
  if (mode == MapServerMode::kRaw) {
    const int8_t value = grid.Value(cell);
    return value < 0 ? kRawUnknownPixel : static_cast<uint8_t>(value);
  }
  switch (grid.State(cell)) {
    case CellState::kFree:
      return kFreePixel;
    case CellState::kOccupied:
      return kOccupiedPixel;
    case CellState::kUnknown:
      return kUnknownPixel;
  }
  return kUnknownPixel;
}

bool EndsWith(const std::string& text, std::string_view suffix) {
  return std::string_view(text).ends_with(suffix);
}

}  // namespace

absl::StatusOr<MapServerMetadata> ParseMapServerYaml(std::string_view yaml_text) {
  ASSIGN_OR_RETURN(const YAML::Node root, internal::LoadYaml(yaml_text, "map YAML"));
  try {
    return MetadataFromNode(root);
  } catch (const YAML::Exception& e) {
    return absl::InvalidArgumentError(absl::StrCat("map YAML: ", e.what()));
  }
}

std::string MapServerYamlToString(const MapServerMetadata& metadata) {
  return absl::StrCat(
      "image: ", internal::YamlScalar(metadata.image), "\n", "mode: ", ModeName(metadata.mode),
      "\n", "resolution: ", FormatDouble(metadata.resolution_m), "\n", "origin: [",
      FormatDouble(metadata.origin.x_m()), ", ", FormatDouble(metadata.origin.y_m()), ", ",
      FormatDouble(metadata.origin.yaw_rad()), "]\n", "negate: ", metadata.negate ? 1 : 0, "\n",
      "occupied_thresh: ", FormatDouble(metadata.occupied_thresh), "\n",
      "free_thresh: ", FormatDouble(metadata.free_thresh), "\n");
}

absl::StatusOr<PgmImage> DecodePgm(std::string_view bytes) {
  // The magic number must be the first two bytes of the file.
  PgmReader reader(bytes);
  const std::string_view magic = bytes.starts_with("P") ? reader.NextToken() : bytes.substr(0, 2);
  if (magic != "P5" && magic != "P2") {
    return absl::InvalidArgumentError(absl::StrCat("PGM: wrong magic '",
                                                   internal::ToAbsl(magic.substr(0, 8)),
                                                   "' (expected P5 binary or P2 ASCII)"));
  }
  ASSIGN_OR_RETURN(const int64_t width, reader.NextInteger("width"));
  ASSIGN_OR_RETURN(const int64_t height, reader.NextInteger("height"));
  RETURN_IF_ERROR(CheckPgmSize(width, height));
  ASSIGN_OR_RETURN(const int64_t max_value, reader.NextInteger("maxval"));
  RETURN_IF_ERROR(CheckMaxValue(max_value));

  PgmImage image;
  image.width = static_cast<int>(width);
  image.height = static_cast<int>(height);
  image.max_value = static_cast<int>(max_value);
  if (magic == "P5") {
    RETURN_IF_ERROR(ReadBinaryRaster(reader, image));
  } else {
    RETURN_IF_ERROR(ReadAsciiRaster(reader, image));
  }
  return image;
}

std::string EncodePgm(const PgmImage& image) {
  const size_t pixel_count = static_cast<size_t>(std::max(image.width, 0)) *
                             static_cast<size_t>(std::max(image.height, 0));
  std::string bytes =
      absl::StrCat("P5\n", image.width, " ", image.height, "\n", kMaxPgmValue, "\n");
  const size_t header_size = bytes.size();
  bytes.resize(header_size + pixel_count, '\0');
  const size_t copied = std::min(pixel_count, image.pixels.size());
  for (size_t i = 0; i < copied; ++i) bytes[header_size + i] = static_cast<char>(image.pixels[i]);
  return bytes;
}

absl::StatusOr<OccupancyGrid> GridFromMapServer(const MapServerMetadata& metadata,
                                                const PgmImage& image) {
  RETURN_IF_ERROR(ValidateMetadata(metadata));
  RETURN_IF_ERROR(CheckPgmSize(image.width, image.height));
  const size_t pixel_count = static_cast<size_t>(image.width) * image.height;
  if (image.pixels.size() != pixel_count) {
    return absl::InvalidArgumentError(absl::StrCat(
        "image has ", image.pixels.size(), " pixels, expected width*height = ", pixel_count));
  }
  if (!image.alpha.empty() && image.alpha.size() != pixel_count) {
    return absl::InvalidArgumentError(
        absl::StrCat("image has ", image.alpha.size(), " alpha values, expected ", pixel_count));
  }
  std::vector<int8_t> cells(pixel_count);
  for (int row = 0; row < image.height; ++row) {
    // The image's top row is the grid's top row (y = height - 1).
    const size_t grid_row = static_cast<size_t>(image.height - 1 - row);
    for (int col = 0; col < image.width; ++col) {
      const size_t i = static_cast<size_t>(row) * image.width + col;
      const bool transparent = !image.alpha.empty() && image.alpha[i] == 0;
      ASSIGN_OR_RETURN(cells[grid_row * image.width + col],
                       CellValueFromPixel(image.pixels[i], transparent, metadata));
    }
  }
  return OccupancyGrid::Create(image.width, image.height, metadata.resolution_m, metadata.origin,
                               std::move(cells));
}

absl::StatusOr<OccupancyGrid> GridFromMapServerBytes(std::string_view yaml_text,
                                                     std::string_view image_bytes) {
  ASSIGN_OR_RETURN(const MapServerMetadata metadata, ParseMapServerYaml(yaml_text));
  ASSIGN_OR_RETURN(const PgmImage image, DecodeMapImage(image_bytes));
  return GridFromMapServer(metadata, image);
}

std::pair<MapServerMetadata, PgmImage> GridToMapServer(const OccupancyGrid& grid,
                                                       const std::string& image_name) {
  MapServerMetadata metadata;
  metadata.image = image_name;
  metadata.resolution_m = grid.resolution_m();
  metadata.origin = grid.origin();
  metadata.negate = false;
  metadata.occupied_thresh = 0.65;
  metadata.free_thresh = 0.196;
  metadata.mode = MapServerMode::kTrinary;
  // Values between free and occupied (a map read in scale or raw mode) survive only as raw.
  for (int y = 0; y < grid.height() && metadata.mode == MapServerMode::kTrinary; ++y) {
    for (int x = 0; x < grid.width(); ++x) {
      const int8_t value = grid.Value(CellIndex{x, y});
      if (value != OccupancyGrid::kFreeValue && value != OccupancyGrid::kOccupiedValue &&
          value != OccupancyGrid::kUnknownValue) {
        metadata.mode = MapServerMode::kRaw;
        break;
      }
    }
  }

  PgmImage image;
  image.width = grid.width();
  image.height = grid.height();
  image.max_value = kMaxPgmValue;
  image.pixels.resize(static_cast<size_t>(grid.width()) * grid.height());
  for (int y = 0; y < grid.height(); ++y) {
    const size_t row = static_cast<size_t>(grid.height() - 1 - y);
    for (int x = 0; x < grid.width(); ++x) {
      image.pixels[row * grid.width() + x] =
          PixelFromCellValue(grid, CellIndex{x, y}, metadata.mode);
    }
  }
  return {std::move(metadata), std::move(image)};
}

uint8_t MapServerGrey(int8_t cell_value) {
  if (cell_value < 0) return kUnknownPixel;
  return static_cast<uint8_t>(std::lround(kFreePixel * (100.0 - cell_value) / 100.0));
}

absl::StatusOr<OccupancyGrid> LoadMapServer(const std::string& yaml_path) {
  ASSIGN_OR_RETURN(const std::string yaml_text, internal::ReadFileToString(yaml_path));
  ASSIGN_OR_RETURN(const MapServerMetadata metadata, ParseMapServerYaml(yaml_text));
  std::filesystem::path image_path(metadata.image);
  if (image_path.is_relative()) {
    image_path = std::filesystem::path(yaml_path).parent_path() / image_path;
  }
  ASSIGN_OR_RETURN(const std::string image_bytes, internal::ReadFileToString(image_path.string()));
  absl::StatusOr<PgmImage> image = DecodeMapImage(image_bytes);
  if (!image.ok()) {
    return absl::Status(image.status().code(),
                        absl::StrCat(image_path.string(), ": ", image.status().message()));
  }
  return GridFromMapServer(metadata, *image);
}

absl::Status SaveMapServer(const OccupancyGrid& grid, const std::string& yaml_path) {
  if (!EndsWith(yaml_path, ".yaml")) {
    return absl::InvalidArgumentError(
        absl::StrCat("map path must end in .yaml, got '", yaml_path, "'"));
  }
  std::filesystem::path pgm_path(yaml_path);
  pgm_path.replace_extension(".pgm");
  const auto [metadata, image] = GridToMapServer(grid, pgm_path.filename().string());
  RETURN_IF_ERROR(internal::WriteStringToFile(pgm_path.string(), EncodePgm(image)));
  return internal::WriteStringToFile(yaml_path, MapServerYamlToString(metadata));
}

}  // namespace fleetnav
