#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "fleetnav/core/occupancy_grid.hpp"

namespace fleetnav {

/// How map_server turns pixel values into occupancy (ROS map_server `mode`).
enum class MapServerMode { kTrinary, kScale, kRaw };

/// The YAML half of a ROS map_server map.
struct MapServerMetadata {
  std::string image;  ///< path of the image (PGM, PNG or BMP), relative to the YAML's folder
  double resolution_m = 0.05;
  Pose2 origin;  ///< [x, y, yaw] of the lower-left pixel
  bool negate = false;
  double occupied_thresh = 0.65;
  double free_thresh = 0.196;
  MapServerMode mode = MapServerMode::kTrinary;
};

/// A decoded map image as 8-bit grey values, top row first as in the file (PGM P5 or P2 of 8
/// or 16 bits, or PNG or BMP through DecodeMapImage).
struct PgmImage {
  int width = 0;
  int height = 0;
  int max_value = 255;
  std::vector<uint8_t> pixels;  ///< row-major, width*height, scaled to 0..255
  /// Opacity per pixel (0 transparent, 255 opaque) when the image has an alpha channel; empty
  /// when it has none.
  std::vector<uint8_t> alpha;
};

absl::StatusOr<MapServerMetadata> ParseMapServerYaml(std::string_view yaml_text);
std::string MapServerYamlToString(const MapServerMetadata& metadata);

/// A PGM: P5 or P2, maxval up to 65535 (samples of 2 bytes, big-endian, above 255), scaled to
/// 0..255.
absl::StatusOr<PgmImage> DecodePgm(std::string_view bytes);
/// Encodes as binary P5 with max value 255.
std::string EncodePgm(const PgmImage& image);

/// Converts an image plus metadata into a grid following map_server's rules (the image's
/// bottom row becomes grid row 0).
absl::StatusOr<OccupancyGrid> GridFromMapServer(const MapServerMetadata& metadata,
                                                const PgmImage& image);
/// Parses a YAML text and image bytes held in memory (an upload; PGM, PNG or BMP).
absl::StatusOr<OccupancyGrid> GridFromMapServerBytes(std::string_view yaml_text,
                                                     std::string_view image_bytes);
/// The P5 image and metadata that reproduce `grid` exactly when read back: trinary (free 254,
/// occupied 0, unknown 205) when every cell is free, occupied or unknown; raw (the cell value
/// as the pixel, unknown 255) when some cell holds a value in between, as a map read in scale
/// or raw mode does (trinary would lose those values).
std::pair<MapServerMetadata, PgmImage> GridToMapServer(const OccupancyGrid& grid,
                                                       const std::string& image_name);

/// The grey map_server shows a cell value in: 0 (free) -> 254, 100 (occupied) -> 0, values in
/// between shaded linearly, unknown (< 0) -> 205 (the trinary image's pixels, for drawing).
uint8_t MapServerGrey(int8_t cell_value);

/// Reads a YAML file and the image it names (relative to the YAML's folder; PGM, PNG or BMP).
absl::StatusOr<OccupancyGrid> LoadMapServer(const std::string& yaml_path);
/// Writes `<stem>.yaml` and `<stem>.pgm` at yaml_path (which must end in .yaml).
absl::Status SaveMapServer(const OccupancyGrid& grid, const std::string& yaml_path);

}  // namespace fleetnav
