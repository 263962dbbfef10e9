#include "fleetnav/proto/zone_convert.hpp"

#include "absl/strings/str_cat.h"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/proto/geometry_convert.hpp"

namespace fleetnav {
namespace {

absl::StatusOr<ZoneKind> KindFromProto(v1::ZoneKind kind, const std::string& field) {
  switch (kind) {
    case v1::ZONE_KIND_NO_GO:
      return ZoneKind::kNoGo;
    case v1::ZONE_KIND_SPEED_LIMIT:
      return ZoneKind::kSpeedLimit;
    case v1::ZONE_KIND_ONE_AT_A_TIME:
      return ZoneKind::kOneAtATime;
    default:
      return absl::InvalidArgumentError(absl::StrCat(
          field, ": must be NO_GO, SPEED_LIMIT or ONE_AT_A_TIME, got ", static_cast<int>(kind)));
  }
}

void PolygonToProto(const Polygon2& polygon, google::protobuf::RepeatedPtrField<v1::Point2>* out) {
  for (const Eigen::Vector2d& vertex : polygon) *out->Add() = ToProto(vertex);
}

/// The vertices, each checked (`field`[j] named when one is not finite).
absl::StatusOr<Polygon2> PolygonFromProto(
    const google::protobuf::RepeatedPtrField<v1::Point2>& polygon, const std::string& field) {
  Polygon2 out;
  out.reserve(polygon.size());
  for (int j = 0; j < polygon.size(); ++j) {
    ASSIGN_OR_RETURN(Eigen::Vector2d vertex,
                     FromProto(polygon.Get(j), absl::StrCat(field, "[", j, "]")));
    out.push_back(vertex);
  }
  return out;
}

}  // namespace

v1::ZoneKind ToProto(ZoneKind kind) {
  switch (kind) {
    case ZoneKind::kNoGo:
      return v1::ZONE_KIND_NO_GO;
    case ZoneKind::kSpeedLimit:
      return v1::ZONE_KIND_SPEED_LIMIT;
    case ZoneKind::kOneAtATime:
      return v1::ZONE_KIND_ONE_AT_A_TIME;
  }
  return v1::ZONE_KIND_UNSPECIFIED;
}

v1::ZoneSet ToProto(const ZoneSet& zones) {
  v1::ZoneSet out;
  out.set_map_id(zones.map_id);
  for (const Zone& zone : zones.zones) {
    v1::Zone* wire = out.add_zones();
    wire->set_name(zone.name);
    wire->set_kind(ToProto(zone.kind));
    PolygonToProto(zone.polygon_in_map, wire->mutable_polygon());
    if (zone.kind == ZoneKind::kSpeedLimit) wire->set_speed_limit_mps(zone.speed_limit_mps);
    if (zone.kind == ZoneKind::kOneAtATime) {
      wire->set_capacity(static_cast<uint32_t>(zone.capacity));
    }
  }
  return out;
}

v1::ZoneSetSummary ToSummaryProto(const ZoneSet& zones, uint32_t version, int64_t created_unix_ms) {
  v1::ZoneSetSummary out;
  out.set_map_id(zones.map_id);
  out.set_version(version);
  out.set_created_unix_ms(created_unix_ms);
  for (const Zone& zone : zones.zones) {
    switch (zone.kind) {
      case ZoneKind::kNoGo:
        out.set_no_go_zones(out.no_go_zones() + 1);
        break;
      case ZoneKind::kSpeedLimit:
        out.set_speed_limit_zones(out.speed_limit_zones() + 1);
        break;
      case ZoneKind::kOneAtATime:
        out.set_one_at_a_time_zones(out.one_at_a_time_zones() + 1);
        break;
    }
  }
  return out;
}

v1::RobotStop ToProto(const RobotStop& stop) {
  v1::RobotStop out;
  out.set_map_id(stop.map_id);
  out.set_zone(stop.zone);
  PolygonToProto(stop.polygon_in_map, out.mutable_polygon());
  out.set_reason(stop.reason);
  out.set_created_unix_ms(stop.created_unix_ms);
  return out;
}

absl::StatusOr<RobotStop> FromProto(const v1::RobotStop& stop) {
  RobotStop out;
  out.map_id = stop.map_id();
  out.zone = stop.zone();
  out.reason = stop.reason();
  out.created_unix_ms = stop.created_unix_ms();
  ASSIGN_OR_RETURN(out.polygon_in_map, PolygonFromProto(stop.polygon(), "stop.polygon"));
  if (out.whole_fleet() && (!out.map_id.empty() || !out.polygon_in_map.empty())) {
    return absl::InvalidArgumentError("stop: a whole-fleet stop has no map and no outline");
  }
  if (!out.whole_fleet() && out.polygon_in_map.size() < 3) {
    return absl::InvalidArgumentError(
        absl::StrCat("stop.polygon: a zone stop needs its outline, got ", out.polygon_in_map.size(),
                     " vertices"));
  }
  return out;
}

absl::StatusOr<ZoneSet> FromProto(const v1::ZoneSet& zones) {
  ZoneSet out;
  out.map_id = zones.map_id();
  out.zones.reserve(zones.zones_size());
  for (int i = 0; i < zones.zones_size(); ++i) {
    const v1::Zone& wire = zones.zones(i);
    const std::string field = absl::StrCat("zones[", i, "]");
    Zone zone;
    zone.name = wire.name();
    ASSIGN_OR_RETURN(zone.kind, KindFromProto(wire.kind(), field + ".kind"));
    ASSIGN_OR_RETURN(zone.polygon_in_map, PolygonFromProto(wire.polygon(), field + ".polygon"));
    if (zone.kind == ZoneKind::kSpeedLimit) {
      zone.speed_limit_mps = wire.speed_limit_mps();
    } else if (wire.speed_limit_mps() != 0.0) {
      return absl::InvalidArgumentError(
          absl::StrCat(field, ".speed_limit_mps: only a speed-limit zone has one"));
    }
    if (zone.kind == ZoneKind::kOneAtATime) {
      if (wire.capacity() > 1000) {
        return absl::InvalidArgumentError(
            absl::StrCat(field, ".capacity: at most 1000 robots, got ", wire.capacity()));
      }
      zone.capacity = wire.capacity() == 0 ? 1 : static_cast<int>(wire.capacity());
    } else if (wire.capacity() != 0) {
      return absl::InvalidArgumentError(
          absl::StrCat(field, ".capacity: only a one-at-a-time zone has one"));
    }
    out.zones.push_back(std::move(zone));
  }
  RETURN_IF_ERROR(out.Validate());
  return out;
}

}  // namespace fleetnav
