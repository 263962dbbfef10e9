// Zone YAML (issue 39): the site layer of no-go, speed-limit and one-at-a-time zones of a map.
#include <yaml-cpp/yaml.h>

#include <string>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/core/zone.hpp"
#include "io_internal.hpp"

namespace fleetnav {
namespace {

using internal::AsDouble;
using internal::FormatDouble;

absl::StatusOr<Polygon2> ParsePolygon(const YAML::Node& node, const std::string& where) {
  if (!node.IsDefined() || node.IsNull()) {
    return absl::InvalidArgumentError(absl::StrCat(where, ": missing 'polygon'"));
  }
  const std::string field = where + ".polygon";
  if (!node.IsSequence()) {
    return absl::InvalidArgumentError(absl::StrCat(field, ": expected a list of [x, y]"));
  }
  Polygon2 polygon;
  for (size_t j = 0; j < node.size(); ++j) {
    const std::string vertex = absl::StrCat(field, "[", j, "]");
    const YAML::Node point = node[j];
    if (!point.IsSequence() || point.size() != 2) {
      return absl::InvalidArgumentError(absl::StrCat(vertex, ": expected [x, y]"));
    }
    ASSIGN_OR_RETURN(const double x, AsDouble(point[0], vertex + "[0]"));
    ASSIGN_OR_RETURN(const double y, AsDouble(point[1], vertex + "[1]"));
    polygon.emplace_back(x, y);
  }
  return polygon;
}

absl::StatusOr<Zone> ParseZone(const YAML::Node& node, size_t index) {
  const std::string where = absl::StrCat("zones[", index, "]");
  if (!node.IsMap()) return absl::InvalidArgumentError(absl::StrCat(where, ": expected a mapping"));
  RETURN_IF_ERROR(internal::CheckKnownKeys(
      node, {"name", "kind", "polygon", "speed_limit", "capacity"}, where));
  Zone zone;
  if (!node["name"]) return absl::InvalidArgumentError(absl::StrCat(where, ": missing 'name'"));
  ASSIGN_OR_RETURN(zone.name, internal::AsString(node["name"], where + ".name"));
  if (!node["kind"]) return absl::InvalidArgumentError(absl::StrCat(where, ": missing 'kind'"));
  ASSIGN_OR_RETURN(const std::string kind, internal::AsString(node["kind"], where + ".kind"));
  absl::StatusOr<ZoneKind> parsed = ParseZoneKind(kind);
  if (!parsed.ok()) {
    return absl::InvalidArgumentError(absl::StrCat(where, ".kind: ", parsed.status().message()));
  }
  zone.kind = *parsed;
  ASSIGN_OR_RETURN(zone.polygon_in_map, ParsePolygon(node["polygon"], where));
  const YAML::Node speed = node["speed_limit"];
  if (zone.kind == ZoneKind::kSpeedLimit) {
    if (!speed) {
      return absl::InvalidArgumentError(
          absl::StrCat(where, ": missing 'speed_limit' (m/s) of a speed_limit zone"));
    }
    ASSIGN_OR_RETURN(zone.speed_limit_mps, AsDouble(speed, where + ".speed_limit"));
  } else if (speed) {
    return absl::InvalidArgumentError(
        absl::StrCat(where, ".speed_limit: only a speed_limit zone has one"));
  }
  const YAML::Node capacity = node["capacity"];
  if (zone.kind == ZoneKind::kOneAtATime) {
    if (capacity) {
      ASSIGN_OR_RETURN(zone.capacity, internal::AsInt(capacity, where + ".capacity"));
    }
  } else if (capacity) {
    return absl::InvalidArgumentError(
        absl::StrCat(where, ".capacity: only a one_at_a_time zone has one"));
  }
  return zone;
}

absl::StatusOr<ZoneSet> ZoneSetFromNode(const YAML::Node& root) {
  if (!root.IsMap()) {
    return absl::InvalidArgumentError("zone YAML: expected a mapping with 'zones' at the top");
  }
  RETURN_IF_ERROR(internal::CheckKnownKeys(root, {"map", "zones"}, "zone YAML"));
  ZoneSet set;
  if (const YAML::Node map = root["map"]; map.IsDefined() && !map.IsNull()) {
    ASSIGN_OR_RETURN(set.map_id, internal::AsString(map, "map"));
  }
  const YAML::Node zones = root["zones"];
  if (!zones.IsDefined()) return absl::InvalidArgumentError("zone YAML: missing 'zones'");
  if (!zones.IsNull()) {
    if (!zones.IsSequence()) return absl::InvalidArgumentError("zones: expected a list");
    for (size_t i = 0; i < zones.size(); ++i) {
      ASSIGN_OR_RETURN(Zone zone, ParseZone(zones[i], i));
      set.zones.push_back(std::move(zone));
    }
  }
  RETURN_IF_ERROR(set.Validate());
  return set;
}

}  // namespace

absl::StatusOr<ZoneSet> ParseZoneSetYaml(std::string_view yaml_text) {
  ASSIGN_OR_RETURN(const YAML::Node root, internal::LoadYaml(yaml_text, "zone YAML"));
  try {
    return ZoneSetFromNode(root);
  } catch (const YAML::Exception& e) {
    return absl::InvalidArgumentError(absl::StrCat("zone YAML: ", e.what()));
  }
}

std::string ZoneSetToYaml(const ZoneSet& zones) {
  std::string text;
  if (!zones.map_id.empty()) {
    absl::StrAppend(&text, "map: ", internal::YamlScalar(zones.map_id), "\n");
  }
  absl::StrAppend(&text, zones.zones.empty() ? "zones: []\n" : "zones:\n");
  for (const Zone& zone : zones.zones) {
    absl::StrAppend(&text, "  - name: ", internal::YamlScalar(zone.name), "\n");
    absl::StrAppend(&text, "    kind: ", internal::ToAbsl(ZoneKindName(zone.kind)), "\n");
    absl::StrAppend(&text, "    polygon: [");
    for (size_t j = 0; j < zone.polygon_in_map.size(); ++j) {
      absl::StrAppend(&text, j == 0 ? "" : ", ", "[", FormatDouble(zone.polygon_in_map[j].x()),
                      ", ", FormatDouble(zone.polygon_in_map[j].y()), "]");
    }
    absl::StrAppend(&text, "]\n");
    if (zone.kind == ZoneKind::kSpeedLimit) {
      absl::StrAppend(&text, "    speed_limit: ", FormatDouble(zone.speed_limit_mps), "\n");
    }
    if (zone.kind == ZoneKind::kOneAtATime) {
      absl::StrAppend(&text, "    capacity: ", zone.capacity, "\n");
    }
  }
  return text;
}

absl::StatusOr<ZoneSet> LoadZoneSet(const std::string& path) {
  ASSIGN_OR_RETURN(const std::string text, internal::ReadFileToString(path));
  absl::StatusOr<ZoneSet> zones = ParseZoneSetYaml(text);
  if (!zones.ok()) {
    return absl::Status(zones.status().code(), absl::StrCat(path, ": ", zones.status().message()));
  }
  return zones;
}

absl::Status SaveZoneSet(const ZoneSet& zones, const std::string& path) {
  RETURN_IF_ERROR(zones.Validate());
  return internal::WriteStringToFile(path, ZoneSetToYaml(zones));
}

}  // namespace fleetnav
