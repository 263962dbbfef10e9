#pragma once

#include <cstdint>
#include <string>

namespace fleetnav {

/// What is known about one stored version of a map, without its cells: its id and version,
/// its size in cells and metres per cell, the operator's description and when it was stored.
struct MapInfo {
  std::string map_id;
  uint32_t version = 0;
  int width = 0;
  int height = 0;
  double resolution_m = 0.0;
  std::string description;
  int64_t created_unix_ms = 0;
};

}  // namespace fleetnav
