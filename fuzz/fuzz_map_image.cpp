// Map images as operators upload them: any bytes through the decoder (PGM, PNG, BMP), and a
// decoded image through map_server's rules into a grid.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fleetnav/core/map_image.hpp"
#include "fleetnav/core/map_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  absl::StatusOr<fleetnav::PgmImage> image = fleetnav::DecodeMapImage(bytes);
  if (!image.ok()) return 0;
  for (fleetnav::MapServerMode mode :
       {fleetnav::MapServerMode::kTrinary, fleetnav::MapServerMode::kScale,
        fleetnav::MapServerMode::kRaw}) {
    fleetnav::MapServerMetadata metadata;
    metadata.mode = mode;
    absl::StatusOr<fleetnav::OccupancyGrid> grid = fleetnav::GridFromMapServer(metadata, *image);
    if (grid.ok()) (void)fleetnav::GridToMapServer(*grid, "x.pgm");
  }
  return 0;
}
