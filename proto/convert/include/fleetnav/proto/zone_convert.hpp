#pragma once

#include <cstdint>

#include "absl/status/statusor.h"
#include "fleetnav/core/robot_stop.hpp"
#include "fleetnav/core/zone.hpp"
#include "fleetnav/v1/fleet_service.pb.h"
#include "fleetnav/v1/types.pb.h"

namespace fleetnav {

/// Wire <-> domain for zone sets. FromProto refuses an unspecified or unknown kind and a
/// non-finite vertex, then validates the set (ZoneSet::Validate), naming the field
/// (`zones[i].kind`, `zones[i].polygon[j]`, …) in InvalidArgument. A capacity of 0 on the wire
/// reads as 1.
v1::ZoneSet ToProto(const ZoneSet& zones);
absl::StatusOr<ZoneSet> FromProto(const v1::ZoneSet& zones);

v1::ZoneKind ToProto(ZoneKind kind);

/// Operators' stops: a polygon of fewer than 3 vertices on a zone stop, or a whole-fleet stop
/// with a map or outline, is InvalidArgument naming the field.
v1::RobotStop ToProto(const RobotStop& stop);
absl::StatusOr<RobotStop> FromProto(const v1::RobotStop& stop);

/// One line of ListZones: the map, its latest version and when it was stored, and how many
/// zones of each kind it holds.
v1::ZoneSetSummary ToSummaryProto(const ZoneSet& zones, uint32_t version, int64_t created_unix_ms);

}  // namespace fleetnav
