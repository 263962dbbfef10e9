// Marker YAML (Lely thesis §5.4.1, eq. 5.5): each stripe marker as a point <x, y, z> on it and
// an orientation quaternion <a, b, c, d> = (x, y, z, w) about the vertical axis.
#include <yaml-cpp/yaml.h>

#include <string>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/core/stripe_marker.hpp"
#include "io_internal.hpp"

namespace fleetnav {
namespace {

using internal::AsDouble;
using internal::FormatDouble;

absl::StatusOr<YAML::Node> RequiredMap(const YAML::Node& parent, const char* key,
                                       const std::string& where) {
  YAML::Node node = parent[key];
  if (!node.IsDefined() || node.IsNull()) {
    return absl::InvalidArgumentError(absl::StrCat(where, ": missing '", key, "'"));
  }
  if (!node.IsMap()) {
    return absl::InvalidArgumentError(absl::StrCat(where, ".", key, ": expected a mapping"));
  }
  return node;
}

absl::StatusOr<double> RequiredDouble(const YAML::Node& parent, const char* key,
                                      const std::string& where) {
  const YAML::Node node = parent[key];
  if (!node.IsDefined() || node.IsNull()) {
    return absl::InvalidArgumentError(absl::StrCat(where, ": missing '", key, "'"));
  }
  return AsDouble(node, absl::StrCat(where, ".", key));
}

absl::Status ParsePosition(const YAML::Node& marker_node, const std::string& where,
                           StripeMarker& marker) {
  ASSIGN_OR_RETURN(const YAML::Node position, RequiredMap(marker_node, "position", where));
  const std::string field = absl::StrCat(where, ".position");
  RETURN_IF_ERROR(internal::CheckKnownKeys(position, {"x", "y", "z"}, field));
  ASSIGN_OR_RETURN(marker.position_m.x(), RequiredDouble(position, "x", field));
  ASSIGN_OR_RETURN(marker.position_m.y(), RequiredDouble(position, "y", field));
  if (position["z"].IsDefined()) {
    ASSIGN_OR_RETURN(marker.z_m, AsDouble(position["z"], field + ".z"));
  }
  return absl::OkStatus();
}

absl::Status ParseOrientation(const YAML::Node& marker_node, const std::string& where,
                              StripeMarker& marker) {
  ASSIGN_OR_RETURN(const YAML::Node orientation, RequiredMap(marker_node, "orientation", where));
  const std::string field = absl::StrCat(where, ".orientation");
  RETURN_IF_ERROR(internal::CheckKnownKeys(orientation, {"a", "b", "c", "d"}, field));
  ASSIGN_OR_RETURN(const double a, RequiredDouble(orientation, "a", field));
  ASSIGN_OR_RETURN(const double b, RequiredDouble(orientation, "b", field));
  ASSIGN_OR_RETURN(const double c, RequiredDouble(orientation, "c", field));
  ASSIGN_OR_RETURN(const double d, RequiredDouble(orientation, "d", field));
  absl::StatusOr<double> yaw_rad = YawFromQuaternion(a, b, c, d);
  if (!yaw_rad.ok()) {
    return absl::InvalidArgumentError(absl::StrCat(field, ": ", yaw_rad.status().message()));
  }
  marker.yaw_rad = *yaw_rad;
  return absl::OkStatus();
}

absl::StatusOr<StripeMarker> ParseMarker(const YAML::Node& node, size_t index) {
  const std::string where = absl::StrCat("markers[", index, "]");
  if (!node.IsMap()) return absl::InvalidArgumentError(absl::StrCat(where, ": expected a mapping"));
  RETURN_IF_ERROR(internal::CheckKnownKeys(
      node, {"id", "position", "orientation", "length", "kind", "stripe"}, where));
  StripeMarker marker;
  const YAML::Node id = node["id"];
  if (!id.IsDefined() || id.IsNull()) {
    return absl::InvalidArgumentError(absl::StrCat(where, ": missing 'id'"));
  }
  ASSIGN_OR_RETURN(marker.id, internal::AsInt(id, where + ".id"));
  RETURN_IF_ERROR(ParsePosition(node, where, marker));
  RETURN_IF_ERROR(ParseOrientation(node, where, marker));
  if (node["length"].IsDefined()) {
    ASSIGN_OR_RETURN(marker.length_m, AsDouble(node["length"], where + ".length"));
  }
  if (node["kind"].IsDefined()) {
    ASSIGN_OR_RETURN(const std::string kind, internal::AsString(node["kind"], where + ".kind"));
    absl::StatusOr<MarkerKind> parsed = ParseMarkerKind(kind);
    if (!parsed.ok()) {
      return absl::InvalidArgumentError(absl::StrCat(where, ".kind: ", parsed.status().message()));
    }
    marker.kind = *parsed;
  }
  if (node["stripe"].IsDefined()) {
    ASSIGN_OR_RETURN(marker.stripe_id, internal::AsInt(node["stripe"], where + ".stripe"));
    if (marker.stripe_id < 0) {
      return absl::InvalidArgumentError(absl::StrCat(where, ".stripe: must be >= 0"));
    }
  }
  return marker;
}

absl::StatusOr<TrolleyPlacement> ParseTrolley(const YAML::Node& node, size_t index) {
  const std::string where = absl::StrCat("trolleys[", index, "]");
  if (!node.IsMap()) return absl::InvalidArgumentError(absl::StrCat(where, ": expected a mapping"));
  RETURN_IF_ERROR(internal::CheckKnownKeys(node, {"id", "pose", "size", "leg_radius"}, where));
  TrolleyPlacement trolley;
  if (!node["id"]) return absl::InvalidArgumentError(absl::StrCat(where, ": missing 'id'"));
  ASSIGN_OR_RETURN(trolley.id, internal::AsString(node["id"], where + ".id"));
  const YAML::Node pose = node["pose"];
  if (!pose || !pose.IsSequence() || pose.size() != 3) {
    return absl::InvalidArgumentError(absl::StrCat(where, ".pose: expected [x, y, yaw_deg]"));
  }
  ASSIGN_OR_RETURN(const double x, internal::AsDouble(pose[0], where + ".pose[0]"));
  ASSIGN_OR_RETURN(const double y, internal::AsDouble(pose[1], where + ".pose[1]"));
  ASSIGN_OR_RETURN(const double yaw_deg, internal::AsDouble(pose[2], where + ".pose[2]"));
  trolley.pose = Pose2(x, y, DegToRad(yaw_deg));
  if (const YAML::Node size = node["size"]; size) {
    if (!size.IsSequence() || size.size() != 2) {
      return absl::InvalidArgumentError(absl::StrCat(where, ".size: expected [x, y]"));
    }
    ASSIGN_OR_RETURN(trolley.size_m.x(), internal::AsDouble(size[0], where + ".size[0]"));
    ASSIGN_OR_RETURN(trolley.size_m.y(), internal::AsDouble(size[1], where + ".size[1]"));
  }
  if (const YAML::Node leg = node["leg_radius"]; leg) {
    ASSIGN_OR_RETURN(trolley.leg_radius_m, internal::AsDouble(leg, where + ".leg_radius"));
  }
  return trolley;
}

absl::StatusOr<MarkerSet> MarkerSetFromNode(const YAML::Node& root) {
  if (!root.IsMap()) {
    return absl::InvalidArgumentError("marker YAML: expected a mapping with 'markers' at the top");
  }
  RETURN_IF_ERROR(internal::CheckKnownKeys(root, {"map", "markers", "trolleys"}, "marker YAML"));
  MarkerSet set;
  if (const YAML::Node map = root["map"]; map.IsDefined() && !map.IsNull()) {
    ASSIGN_OR_RETURN(set.map_id, internal::AsString(map, "map"));
  }
  const YAML::Node markers = root["markers"];
  if (!markers.IsDefined()) return absl::InvalidArgumentError("marker YAML: missing 'markers'");
  if (!markers.IsNull()) {
    if (!markers.IsSequence()) return absl::InvalidArgumentError("markers: expected a list");
    for (size_t i = 0; i < markers.size(); ++i) {
      ASSIGN_OR_RETURN(StripeMarker marker, ParseMarker(markers[i], i));
      set.markers.push_back(marker);
    }
  }
  if (const YAML::Node trolleys = root["trolleys"]; trolleys.IsDefined() && !trolleys.IsNull()) {
    if (!trolleys.IsSequence()) return absl::InvalidArgumentError("trolleys: expected a list");
    for (size_t i = 0; i < trolleys.size(); ++i) {
      ASSIGN_OR_RETURN(TrolleyPlacement trolley, ParseTrolley(trolleys[i], i));
      set.trolleys.push_back(trolley);
    }
  }
  RETURN_IF_ERROR(set.Validate());
  return set;
}

}  // namespace

absl::StatusOr<MarkerSet> ParseMarkerSetYaml(std::string_view yaml_text) {
  ASSIGN_OR_RETURN(const YAML::Node root, internal::LoadYaml(yaml_text, "marker YAML"));
  try {
    return MarkerSetFromNode(root);
  } catch (const YAML::Exception& e) {
    return absl::InvalidArgumentError(absl::StrCat("marker YAML: ", e.what()));
  }
}

std::string MarkerSetToYaml(const MarkerSet& markers) {
  std::string text;
  if (!markers.map_id.empty()) {
    absl::StrAppend(&text, "map: ", internal::YamlScalar(markers.map_id), "\n");
  }
  if (markers.markers.empty()) absl::StrAppend(&text, "markers: []\n");
  if (!markers.markers.empty()) absl::StrAppend(&text, "markers:\n");
  for (const StripeMarker& marker : markers.markers) {
    const Eigen::Vector4d q = QuaternionFromYaw(marker.yaw_rad);
    absl::StrAppend(&text, "  - id: ", marker.id, "\n");
    absl::StrAppend(&text, "    position: {x: ", FormatDouble(marker.position_m.x()),
                    ", y: ", FormatDouble(marker.position_m.y()), ", z: ", FormatDouble(marker.z_m),
                    "}\n");
    absl::StrAppend(&text, "    orientation: {a: ", FormatDouble(q[0]), ", b: ", FormatDouble(q[1]),
                    ", c: ", FormatDouble(q[2]), ", d: ", FormatDouble(q[3]), "}\n");
    absl::StrAppend(&text, "    length: ", FormatDouble(marker.length_m), "\n");
    absl::StrAppend(&text, "    kind: ", internal::ToAbsl(MarkerKindName(marker.kind)), "\n");
    if (marker.stripe_id != 0) absl::StrAppend(&text, "    stripe: ", marker.stripe_id, "\n");
  }
  if (!markers.trolleys.empty()) absl::StrAppend(&text, "trolleys:\n");
  for (const TrolleyPlacement& t : markers.trolleys) {
    absl::StrAppend(&text, "  - {id: ", internal::YamlScalar(t.id), ", pose: [",
                    FormatDouble(t.pose.x_m()), ", ", FormatDouble(t.pose.y_m()), ", ",
                    FormatDouble(RadToDeg(t.pose.yaw_rad())), "], size: [",
                    FormatDouble(t.size_m.x()), ", ", FormatDouble(t.size_m.y()),
                    "], leg_radius: ", FormatDouble(t.leg_radius_m), "}\n");
  }
  return text;
}

absl::StatusOr<MarkerSet> LoadMarkerSet(const std::string& path) {
  ASSIGN_OR_RETURN(const std::string text, internal::ReadFileToString(path));
  absl::StatusOr<MarkerSet> markers = ParseMarkerSetYaml(text);
  if (!markers.ok()) {
    return absl::Status(markers.status().code(),
                        absl::StrCat(path, ": ", markers.status().message()));
  }
  return markers;
}

absl::Status SaveMarkerSet(const MarkerSet& markers, const std::string& path) {
  RETURN_IF_ERROR(markers.Validate());
  return internal::WriteStringToFile(path, MarkerSetToYaml(markers));
}

}  // namespace fleetnav
