#pragma once

#include <cstddef>
#include <cstdint>

#include "absl/status/statusor.h"
#include "fleetnav/core/occupancy_grid.hpp"

namespace fleetnav::loc_bench {

/// A 20 m × 20 m map at 5 cm with walls and scattered boxes (the benchmark map of issue 5).
absl::StatusOr<OccupancyGrid> BenchMap(uint64_t seed);

}  // namespace fleetnav::loc_bench
