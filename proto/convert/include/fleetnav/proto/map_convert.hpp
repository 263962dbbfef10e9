#pragma once

#include <string>

#include "absl/status/statusor.h"
#include "fleetnav/core/occupancy_grid.hpp"
#include "fleetnav/core/stripe_marker.hpp"
#include "fleetnav/v1/types.pb.h"

namespace fleetnav {

/// Wire <-> domain for grids and stripe markers. FromProto validates (cell count, resolution,
/// enum values, duplicate ids) and names the offending field in InvalidArgument.
v1::OccupancyGrid ToProto(const OccupancyGrid& grid);
absl::StatusOr<OccupancyGrid> FromProto(const v1::OccupancyGrid& grid);

v1::StripeMarker ToProto(const StripeMarker& marker);
absl::StatusOr<StripeMarker> FromProto(const v1::StripeMarker& marker,
                                       const std::string& field = "marker");

v1::MarkerSet ToProto(const MarkerSet& markers);
absl::StatusOr<MarkerSet> FromProto(const v1::MarkerSet& markers);

}  // namespace fleetnav
