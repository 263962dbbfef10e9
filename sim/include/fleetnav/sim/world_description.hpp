#pragma once

#include <Eigen/Core>
#include <string>
#include <string_view>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/stripe_marker.hpp"

namespace fleetnav::sim {

/// A solid box standing on the floor: centre, size along its own x/y, yaw, height.
struct BoxObstacle {
  std::string kind;  ///< "wall", "fence", "box", "shelf", ...
  Eigen::Vector2d center_m = Eigen::Vector2d::Zero();
  Eigen::Vector2d size_m = Eigen::Vector2d::Ones();
  double yaw_rad = 0.0;
  double height_m = 1.0;
};

/// A vertical cylinder (post, trolley leg, charging pole).
struct CylinderObstacle {
  std::string kind;
  Eigen::Vector2d center_m = Eigen::Vector2d::Zero();
  double radius_m = 0.1;
  double height_m = 1.0;
};

/// A metal floor stripe as a polyline (follow stripes are numbered).
struct FloorStripe {
  int id = 0;
  std::vector<Eigen::Vector2d> points_m;
  double width_m = 0.05;
};

/// A robot placed in the world at start.
struct RobotSpawn {
  std::string robot_id;
  std::string kind_name;
  Pose2 pose;
};

/// A simulated site as data: its extent, solid obstacles, floor stripes, stripe markers and
/// robots at start. The occupancy map and the marker set are generated from it (see
/// world_rasterizer.hpp) so that map and world cannot diverge. Value type.
struct WorldDescription {
  std::string name;
  Eigen::Vector2d min_corner_m = Eigen::Vector2d::Zero();
  Eigen::Vector2d max_corner_m = Eigen::Vector2d(10, 10);
  std::vector<BoxObstacle> boxes;
  std::vector<CylinderObstacle> cylinders;
  std::vector<FloorStripe> stripes;
  std::vector<StripeMarker> markers;
  std::vector<RobotSpawn> robots;
};

/// World YAML (see docs/file-formats.md):
///   name: barn
///   extent: {min: [-13, -13], max: [13, 13]}
///   walls:     [{from: [x, y], to: [x, y], thickness: 0.2, height: 2.5}]
///   fences:    [{from: [x, y], to: [x, y], thickness: 0.1, height: 1.2}]
///   boxes:     [{center: [x, y], size: [w, d], yaw_deg: 0, height: 1, kind: box}]
///   cylinders: [{center: [x, y], radius: 0.1, height: 1.5, kind: post}]
///   stripes:   [{id: 1, points: [[x, y], [x, y]], width: 0.05}]
///   markers:   [{id: 1, at: [x, y], yaw_deg: 90, length: 0.6}]
///   robots:    [{id: lely1, kind: lely-vector, pose: [x, y, yaw_deg]}]
/// Errors are InvalidArgument naming the list and index, e.g. "walls[2].to: expected [x, y]".
absl::StatusOr<WorldDescription> ParseWorldYaml(std::string_view yaml_text);
absl::StatusOr<WorldDescription> LoadWorld(const std::string& path);

}  // namespace fleetnav::sim
