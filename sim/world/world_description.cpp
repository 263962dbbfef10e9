#include "fleetnav/sim/world_description.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/sim/geometry2d.hpp"

namespace fleetnav::sim {
namespace {

absl::StatusOr<Eigen::Vector2d> ReadPoint(const YAML::Node& node, const std::string& field) {
  if (!node || !node.IsSequence() || node.size() != 2) {
    return absl::InvalidArgumentError(absl::StrCat(field, ": expected [x, y]"));
  }
  Eigen::Vector2d p(node[0].as<double>(), node[1].as<double>());
  if (!p.allFinite()) return absl::InvalidArgumentError(absl::StrCat(field, ": not finite"));
  return p;
}

absl::StatusOr<double> ReadPositive(const YAML::Node& node, const std::string& field,
                                    double fallback) {
  const double value = node ? node.as<double>() : fallback;
  if (!std::isfinite(value) || value <= 0.0) {
    return absl::InvalidArgumentError(absl::StrCat(field, ": must be > 0, got ", value));
  }
  return value;
}

// A wall or fence given as a segment becomes a box along it.
absl::StatusOr<BoxObstacle> SegmentBox(const YAML::Node& node, const std::string& field,
                                       const std::string& kind, double default_thickness,
                                       double default_height) {
  ASSIGN_OR_RETURN(Eigen::Vector2d from, ReadPoint(node["from"], field + ".from"));
  ASSIGN_OR_RETURN(Eigen::Vector2d to, ReadPoint(node["to"], field + ".to"));
  const double length = (to - from).norm();
  if (length <= 1e-6) {
    return absl::InvalidArgumentError(absl::StrCat(field, ": from and to are the same point"));
  }
  ASSIGN_OR_RETURN(double thickness,
                   ReadPositive(node["thickness"], field + ".thickness", default_thickness));
  ASSIGN_OR_RETURN(double height, ReadPositive(node["height"], field + ".height", default_height));
  BoxObstacle box;
  box.kind = kind;
  box.center_m = 0.5 * (from + to);
  box.size_m = Eigen::Vector2d(length, thickness);
  box.yaw_rad = std::atan2(to.y() - from.y(), to.x() - from.x());
  box.height_m = height;
  return box;
}

// The number of entries of an optional list. yaml-cpp throws on size() of a missing key of a
// const node, so a world without, say, cylinders would fail to parse.
size_t ListSize(const YAML::Node& root, const char* key) {
  const YAML::Node list = root[key];
  return list ? list.size() : 0;
}

absl::StatusOr<WorldDescription> ParseRoot(const YAML::Node& root) {
  WorldDescription world;
  if (!root.IsMap()) return absl::InvalidArgumentError("world: expected a YAML mapping");
  world.name = root["name"] ? root["name"].as<std::string>() : "world";
  const YAML::Node extent = root["extent"];
  if (!extent) return absl::InvalidArgumentError("extent: missing ({min: [x, y], max: [x, y]})");
  ASSIGN_OR_RETURN(world.min_corner_m, ReadPoint(extent["min"], "extent.min"));
  ASSIGN_OR_RETURN(world.max_corner_m, ReadPoint(extent["max"], "extent.max"));
  if ((world.max_corner_m - world.min_corner_m).minCoeff() <= 0.0) {
    return absl::InvalidArgumentError("extent: max must exceed min in x and y");
  }
  for (size_t i = 0; i < ListSize(root, "walls"); ++i) {
    ASSIGN_OR_RETURN(BoxObstacle box, SegmentBox(root["walls"][i], absl::StrCat("walls[", i, "]"),
                                                 "wall", 0.2, 2.5));
    world.boxes.push_back(box);
  }
  for (size_t i = 0; i < ListSize(root, "fences"); ++i) {
    ASSIGN_OR_RETURN(BoxObstacle box, SegmentBox(root["fences"][i], absl::StrCat("fences[", i, "]"),
                                                 "fence", 0.1, 1.2));
    world.boxes.push_back(box);
  }
  for (size_t i = 0; i < ListSize(root, "boxes"); ++i) {
    const YAML::Node node = root["boxes"][i];
    const std::string field = absl::StrCat("boxes[", i, "]");
    BoxObstacle box;
    box.kind = node["kind"] ? node["kind"].as<std::string>() : "box";
    ASSIGN_OR_RETURN(box.center_m, ReadPoint(node["center"], field + ".center"));
    ASSIGN_OR_RETURN(box.size_m, ReadPoint(node["size"], field + ".size"));
    if (box.size_m.minCoeff() <= 0.0) {
      return absl::InvalidArgumentError(absl::StrCat(field, ".size: must be > 0"));
    }
    box.yaw_rad = DegToRad(node["yaw_deg"] ? node["yaw_deg"].as<double>() : 0.0);
    ASSIGN_OR_RETURN(box.height_m, ReadPositive(node["height"], field + ".height", 1.0));
    world.boxes.push_back(box);
  }
  for (size_t i = 0; i < ListSize(root, "cylinders"); ++i) {
    const YAML::Node node = root["cylinders"][i];
    const std::string field = absl::StrCat("cylinders[", i, "]");
    CylinderObstacle cylinder;
    cylinder.kind = node["kind"] ? node["kind"].as<std::string>() : "post";
    ASSIGN_OR_RETURN(cylinder.center_m, ReadPoint(node["center"], field + ".center"));
    ASSIGN_OR_RETURN(cylinder.radius_m, ReadPositive(node["radius"], field + ".radius", 0.1));
    ASSIGN_OR_RETURN(cylinder.height_m, ReadPositive(node["height"], field + ".height", 1.5));
    world.cylinders.push_back(cylinder);
  }
  for (size_t i = 0; i < ListSize(root, "trolleys"); ++i) {
    const YAML::Node node = root["trolleys"][i];
    const std::string field = absl::StrCat("trolleys[", i, "]");
    Trolley trolley;
    trolley.id = node["id"] ? node["id"].as<std::string>() : absl::StrCat("trolley-", i + 1);
    for (const Trolley& other : world.trolleys) {
      if (other.id == trolley.id) {
        return absl::InvalidArgumentError(
            absl::StrCat(field, ".id: duplicate trolley id '", trolley.id, "'"));
      }
    }
    ASSIGN_OR_RETURN(trolley.center_m, ReadPoint(node["center"], field + ".center"));
    if (node["size"]) {
      ASSIGN_OR_RETURN(trolley.size_m, ReadPoint(node["size"], field + ".size"));
    }
    if (trolley.size_m.minCoeff() <= 0.0) {
      return absl::InvalidArgumentError(absl::StrCat(field, ".size: must be > 0"));
    }
    trolley.yaw_rad = DegToRad(node["yaw_deg"] ? node["yaw_deg"].as<double>() : 0.0);
    ASSIGN_OR_RETURN(trolley.leg_radius_m,
                     ReadPositive(node["leg_radius"], field + ".leg_radius", 0.02));
    world.trolleys.push_back(trolley);
  }
  for (size_t i = 0; i < ListSize(root, "faults"); ++i) {
    const YAML::Node node = root["faults"][i];
    const std::string field = absl::StrCat("faults[", i, "]");
    FaultSpec fault;
    if (!node["type"]) return absl::InvalidArgumentError(absl::StrCat(field, ".type: missing"));
    absl::StatusOr<FaultType> type = FaultTypeByName(node["type"].as<std::string>());
    if (!type.ok()) {
      return absl::InvalidArgumentError(absl::StrCat(field, ".type: ", type.status().message()));
    }
    fault.type = *type;
    fault.label = node["label"] ? node["label"].as<std::string>() : "";
    if (node["region"]) {
      ASSIGN_OR_RETURN(fault.region_min_m, ReadPoint(node["region"]["min"], field + ".region.min"));
      ASSIGN_OR_RETURN(fault.region_max_m, ReadPoint(node["region"]["max"], field + ".region.max"));
    }
    if (fault.IsRegionFault() && (fault.region_max_m - fault.region_min_m).minCoeff() <= 0.0) {
      return absl::InvalidArgumentError(
          absl::StrCat(field, ".region: max must exceed min in x and y"));
    }
    fault.robot_id = node["robot"] ? node["robot"].as<std::string>() : "";
    fault.sensor_name = node["sensor"] ? node["sensor"].as<std::string>() : "";
    fault.duration_s = node["duration_s"] ? node["duration_s"].as<double>() : 0.0;
    fault.factor = node["factor"] ? node["factor"].as<double>() : 1.0;
    world.faults.push_back(fault);
  }
  for (size_t i = 0; i < ListSize(root, "stripes"); ++i) {
    const YAML::Node node = root["stripes"][i];
    const std::string field = absl::StrCat("stripes[", i, "]");
    FloorStripe stripe;
    stripe.id = node["id"].as<int>();
    for (size_t k = 0; k < node["points"].size(); ++k) {
      ASSIGN_OR_RETURN(Eigen::Vector2d p,
                       ReadPoint(node["points"][k], absl::StrCat(field, ".points[", k, "]")));
      stripe.points_m.push_back(p);
    }
    if (stripe.points_m.size() < 2) {
      return absl::InvalidArgumentError(absl::StrCat(field, ".points: needs at least 2 points"));
    }
    ASSIGN_OR_RETURN(stripe.width_m, ReadPositive(node["width"], field + ".width", 0.05));
    if (node["kind"]) {
      const std::string kind = node["kind"].as<std::string>();
      if (kind != "follow" && kind != "charger") {
        return absl::InvalidArgumentError(
            absl::StrCat(field, ".kind: '", kind, "' is not a stripe kind (follow, charger)"));
      }
      stripe.charger = kind == "charger";
    }
    world.stripes.push_back(stripe);
  }
  for (size_t i = 0; i < ListSize(root, "markers"); ++i) {
    const YAML::Node node = root["markers"][i];
    const std::string field = absl::StrCat("markers[", i, "]");
    StripeMarker marker;
    marker.id = node["id"].as<int>();
    ASSIGN_OR_RETURN(marker.position_m, ReadPoint(node["at"], field + ".at"));
    marker.yaw_rad =
        NormalizeMarkerYaw(DegToRad(node["yaw_deg"] ? node["yaw_deg"].as<double>() : 0));
    ASSIGN_OR_RETURN(marker.length_m, ReadPositive(node["length"], field + ".length", 0.6));
    world.markers.push_back(marker);
  }
  for (size_t i = 0; i < ListSize(root, "robots"); ++i) {
    const YAML::Node node = root["robots"][i];
    const std::string field = absl::StrCat("robots[", i, "]");
    RobotSpawn spawn;
    spawn.robot_id = node["id"].as<std::string>();
    spawn.kind_name = node["kind"].as<std::string>();
    const YAML::Node pose = node["pose"];
    if (!pose || !pose.IsSequence() || pose.size() != 3) {
      return absl::InvalidArgumentError(absl::StrCat(field, ".pose: expected [x, y, yaw_deg]"));
    }
    spawn.pose = Pose2(pose[0].as<double>(), pose[1].as<double>(), DegToRad(pose[2].as<double>()));
    for (const RobotSpawn& other : world.robots) {
      if (other.robot_id == spawn.robot_id) {
        return absl::InvalidArgumentError(
            absl::StrCat(field, ".id: '", spawn.robot_id, "' is already a robot of this world"));
      }
    }
    world.robots.push_back(spawn);
  }
  return world;
}

// The parts of segment a→b outside the rectangle, as parameter intervals.
std::vector<std::pair<double, double>> OutsideParts(const Eigen::Vector2d& a,
                                                    const Eigen::Vector2d& b,
                                                    const FaultSpec& region) {
  const auto inside = ClipSegment(a, b, region.region_min_m, region.region_max_m);
  if (!inside) return {{0.0, 1.0}};
  std::vector<std::pair<double, double>> out;
  if (inside->first > 1e-9) out.push_back({0.0, inside->first});
  if (inside->second < 1.0 - 1e-9) out.push_back({inside->second, 1.0});
  return out;
}

// Fences inside the region lose that part: a fence box is cut along its length.
void RemoveFence(const FaultSpec& region, WorldDescription* world) {
  std::vector<BoxObstacle> boxes;
  for (const BoxObstacle& box : world->boxes) {
    if (box.kind != "fence") {
      boxes.push_back(box);
      continue;
    }
    const Eigen::Vector2d axis(std::cos(box.yaw_rad), std::sin(box.yaw_rad));
    const Eigen::Vector2d a = box.center_m - 0.5 * box.size_m.x() * axis;
    const Eigen::Vector2d b = box.center_m + 0.5 * box.size_m.x() * axis;
    for (const auto& [t0, t1] : OutsideParts(a, b, region)) {
      const double length = (t1 - t0) * box.size_m.x();
      if (length < 1e-3) continue;
      BoxObstacle part = box;
      part.center_m = a + 0.5 * (t0 + t1) * (b - a);
      part.size_m.x() = length;
      boxes.push_back(part);
    }
  }
  world->boxes = std::move(boxes);
}

// Stripes inside the region lose that part (a polyline may fall apart into several).
void RemoveStripe(const FaultSpec& region, WorldDescription* world) {
  std::vector<FloorStripe> stripes;
  for (const FloorStripe& stripe : world->stripes) {
    FloorStripe current = stripe;
    current.points_m.clear();
    auto flush = [&] {
      if (current.points_m.size() >= 2) stripes.push_back(current);
      current.points_m.clear();
    };
    for (size_t i = 0; i + 1 < stripe.points_m.size(); ++i) {
      const Eigen::Vector2d& a = stripe.points_m[i];
      const Eigen::Vector2d& b = stripe.points_m[i + 1];
      for (const auto& [t0, t1] : OutsideParts(a, b, region)) {
        const Eigen::Vector2d p0 = a + t0 * (b - a);
        const Eigen::Vector2d p1 = a + t1 * (b - a);
        if (current.points_m.empty() || (current.points_m.back() - p0).norm() > 1e-9) {
          flush();
          current.points_m.push_back(p0);
        }
        current.points_m.push_back(p1);
      }
    }
    flush();
  }
  world->stripes = std::move(stripes);
}

}  // namespace

void ApplyGeometryFault(const FaultSpec& fault, WorldDescription* world) {
  if (fault.type == FaultType::kRemoveFenceSegment) RemoveFence(fault, world);
  if (fault.type == FaultType::kRemoveStripeSegment) RemoveStripe(fault, world);
}

absl::StatusOr<WorldDescription> ParseWorldYaml(std::string_view yaml_text) {
  try {
    return ParseRoot(YAML::Load(std::string(yaml_text)));
  } catch (const YAML::Exception& e) {
    return absl::InvalidArgumentError(absl::StrCat("world YAML: ", e.what()));
  }
}

namespace {

/// The world file's YAML with its `extends` chain resolved: the base file (relative to this
/// one) first, then this file's keys — lists appended to the base's, other keys replacing.
absl::StatusOr<YAML::Node> LoadWorldNode(const std::filesystem::path& path, int depth) {
  if (depth > 8) {
    return absl::InvalidArgumentError(
        absl::StrCat("extends: more than 8 files deep at ", path.string()));
  }
  std::ifstream in(path);
  if (!in) {
    return absl::NotFoundError(absl::StrCat("cannot open world file '", path.string(), "'"));
  }
  std::stringstream text;
  text << in.rdbuf();
  YAML::Node node;
  try {
    node = YAML::Load(text.str());
  } catch (const YAML::Exception& e) {
    return absl::InvalidArgumentError(absl::StrCat(path.string(), ": world YAML: ", e.what()));
  }
  if (!node.IsMap() || !node["extends"]) return node;
  if (!node["extends"].IsScalar()) {
    return absl::InvalidArgumentError(
        absl::StrCat(path.string(), ": extends: expected the path of a world file"));
  }
  ASSIGN_OR_RETURN(
      YAML::Node merged,
      LoadWorldNode(path.parent_path() / node["extends"].as<std::string>(), depth + 1));
  for (const auto& entry : node) {
    const std::string key = entry.first.as<std::string>();
    if (key == "extends") continue;
    if (entry.second.IsSequence() && merged[key] && merged[key].IsSequence()) {
      for (const YAML::Node& item : entry.second) merged[key].push_back(item);
    } else {
      merged[key] = entry.second;
    }
  }
  return merged;
}

}  // namespace

absl::StatusOr<WorldDescription> LoadWorld(const std::string& path) {
  absl::StatusOr<YAML::Node> node = LoadWorldNode(path, 0);
  if (!node.ok()) return node.status();
  absl::StatusOr<WorldDescription> world;
  try {
    world = ParseRoot(*node);
  } catch (const YAML::Exception& e) {
    world = absl::InvalidArgumentError(absl::StrCat("world YAML: ", e.what()));
  }
  if (!world.ok()) {
    return absl::Status(world.status().code(), absl::StrCat(path, ": ", world.status().message()));
  }
  return world;
}

}  // namespace fleetnav::sim
