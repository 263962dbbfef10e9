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
  std::string image;  ///< path of the PGM, relative to the YAML file's folder
  double resolution_m = 0.05;
  Pose2 origin;  ///< [x, y, yaw] of the lower-left pixel
  bool negate = false;
  double occupied_thresh = 0.65;
  double free_thresh = 0.196;
  MapServerMode mode = MapServerMode::kTrinary;
};

/// A decoded 8-bit PGM image (P5 binary or P2 ASCII), top row first as in the file.
struct PgmImage {
  int width = 0;
  int height = 0;
  int max_value = 255;
  std::vector<uint8_t> pixels;  ///< row-major, width*height, scaled to 0..255
};

absl::StatusOr<MapServerMetadata> ParseMapServerYaml(std::string_view yaml_text);
std::string MapServerYamlToString(const MapServerMetadata& metadata);

absl::StatusOr<PgmImage> DecodePgm(std::string_view bytes);
/// Encodes as binary P5 with max value 255.
std::string EncodePgm(const PgmImage& image);

/// Converts an image plus metadata into a grid following map_server's rules (the image's
/// bottom row becomes grid row 0).
absl::StatusOr<OccupancyGrid> GridFromMapServer(const MapServerMetadata& metadata,
                                                const PgmImage& image);
/// Parses a YAML text and PGM bytes held in memory (an upload).
absl::StatusOr<OccupancyGrid> GridFromMapServerBytes(std::string_view yaml_text,
                                                     std::string_view pgm_bytes);
/// The trinary P5 image and metadata that reproduce `grid` exactly when read back
/// (free 254, occupied 0, unknown 205).
std::pair<MapServerMetadata, PgmImage> GridToMapServer(const OccupancyGrid& grid,
                                                       const std::string& image_name);

/// Reads a YAML file and the PGM it names (relative to the YAML's folder).
absl::StatusOr<OccupancyGrid> LoadMapServer(const std::string& yaml_path);
/// Writes `<stem>.yaml` and `<stem>.pgm` at yaml_path (which must end in .yaml).
absl::Status SaveMapServer(const OccupancyGrid& grid, const std::string& yaml_path);

}  // namespace fleetnav
