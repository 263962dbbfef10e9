#include "fleetnav/proto/map_convert.hpp"

#include <cmath>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/proto/geometry_convert.hpp"

namespace fleetnav {

v1::OccupancyGrid ToProto(const OccupancyGrid& grid) {
  v1::OccupancyGrid out;
  out.set_width(static_cast<uint32_t>(grid.width()));
  out.set_height(static_cast<uint32_t>(grid.height()));
  out.set_resolution_m(grid.resolution_m());
  *out.mutable_origin() = ToProto(grid.origin());
  const auto& cells = grid.cells();
  out.set_cells(std::string(reinterpret_cast<const char*>(cells.data()), cells.size()));
  return out;
}

absl::StatusOr<OccupancyGrid> FromProto(const v1::OccupancyGrid& grid) {
  const uint64_t expected = static_cast<uint64_t>(grid.width()) * grid.height();
  if (expected > static_cast<uint64_t>(kMaxGridCells)) {
    return absl::InvalidArgumentError(absl::StrCat("grid: width × height = ", expected,
                                                   " cells exceeds the limit of ", kMaxGridCells));
  }
  if (grid.cells().size() != expected) {
    return absl::InvalidArgumentError(absl::StrCat("grid.cells: width × height = ", grid.width(),
                                                   " × ", grid.height(), " = ", expected, " but ",
                                                   grid.cells().size(), " cells were sent"));
  }
  ASSIGN_OR_RETURN(Pose2 origin, FromProto(grid.origin(), "grid.origin"));
  std::vector<int8_t> cells(grid.cells().begin(), grid.cells().end());
  return OccupancyGrid::Create(static_cast<int>(grid.width()), static_cast<int>(grid.height()),
                               grid.resolution_m(), origin, std::move(cells));
}

namespace {

v1::MarkerKind ToProto(MarkerKind kind) {
  switch (kind) {
    case MarkerKind::kCalibration:
      return v1::MARKER_KIND_CALIBRATION;
    case MarkerKind::kFollowStripe:
      return v1::MARKER_KIND_FOLLOW_STRIPE;
    case MarkerKind::kChargerStripe:
      return v1::MARKER_KIND_CHARGER_STRIPE;
  }
  return v1::MARKER_KIND_UNSPECIFIED;
}

absl::StatusOr<MarkerKind> MarkerKindFromProto(int kind, const std::string& field) {
  switch (kind) {
    case v1::MARKER_KIND_UNSPECIFIED:  // optional on the wire: calibration is the default
    case v1::MARKER_KIND_CALIBRATION:
      return MarkerKind::kCalibration;
    case v1::MARKER_KIND_FOLLOW_STRIPE:
      return MarkerKind::kFollowStripe;
    case v1::MARKER_KIND_CHARGER_STRIPE:
      return MarkerKind::kChargerStripe;
    default:
      return absl::InvalidArgumentError(absl::StrCat(field, ".kind: unknown value ", kind));
  }
}

}  // namespace

v1::StripeMarker ToProto(const StripeMarker& marker) {
  v1::StripeMarker out;
  out.set_id(marker.id);
  *out.mutable_pose() =
      ToProto(Pose2(marker.position_m.x(), marker.position_m.y(), marker.yaw_rad));
  out.set_length_m(marker.length_m);
  out.set_kind(ToProto(marker.kind));
  out.set_z_m(marker.z_m);
  out.set_stripe_id(marker.stripe_id);
  return out;
}

absl::StatusOr<StripeMarker> FromProto(const v1::StripeMarker& marker, const std::string& field) {
  StripeMarker out;
  out.id = marker.id();
  const std::string pose_field = absl::StrCat(field, ".pose");
  ASSIGN_OR_RETURN(Pose2 pose, FromProto(marker.pose(), pose_field));
  out.position_m = pose.translation();
  out.yaw_rad = NormalizeMarkerYaw(marker.pose().yaw_rad());
  out.z_m = marker.z_m();
  if (!std::isfinite(out.z_m)) {
    return absl::InvalidArgumentError(absl::StrCat(field, ".z_m must be finite"));
  }
  out.length_m = marker.length_m();
  if (!std::isfinite(out.length_m) || out.length_m <= 0.0) {
    return absl::InvalidArgumentError(
        absl::StrCat(field, ".length_m must be finite and > 0, got ", out.length_m));
  }
  ASSIGN_OR_RETURN(out.kind, MarkerKindFromProto(marker.kind(), field));
  out.stripe_id = marker.stripe_id();
  if (out.stripe_id < 0) {
    return absl::InvalidArgumentError(absl::StrCat(field, ".stripe_id must be >= 0"));
  }
  return out;
}

v1::MarkerSet ToProto(const MarkerSet& markers) {
  v1::MarkerSet out;
  out.set_map_id(markers.map_id);
  for (const StripeMarker& marker : markers.markers) *out.add_markers() = ToProto(marker);
  for (const TrolleyPlacement& trolley : markers.trolleys) {
    v1::TrolleyPlacement* wire = out.add_trolleys();
    wire->set_id(trolley.id);
    *wire->mutable_pose() = ToProto(trolley.pose);
    *wire->mutable_size() = ToProto(trolley.size_m);
    wire->set_leg_radius_m(trolley.leg_radius_m);
  }
  return out;
}

absl::StatusOr<MarkerSet> FromProto(const v1::MarkerSet& markers) {
  MarkerSet out;
  out.map_id = markers.map_id();
  out.markers.reserve(markers.markers_size());
  for (int i = 0; i < markers.markers_size(); ++i) {
    ASSIGN_OR_RETURN(StripeMarker marker,
                     FromProto(markers.markers(i), absl::StrCat("markers[", i, "]")));
    out.markers.push_back(marker);
  }
  for (int i = 0; i < markers.trolleys_size(); ++i) {
    const v1::TrolleyPlacement& wire = markers.trolleys(i);
    const std::string field = absl::StrCat("trolleys[", i, "]");
    TrolleyPlacement trolley;
    trolley.id = wire.id();
    ASSIGN_OR_RETURN(trolley.pose, FromProto(wire.pose(), field + ".pose"));
    ASSIGN_OR_RETURN(trolley.size_m, FromProto(wire.size(), field + ".size"));
    trolley.leg_radius_m = wire.leg_radius_m();
    out.trolleys.push_back(trolley);
  }
  RETURN_IF_ERROR(out.Validate());
  return out;
}

}  // namespace fleetnav
