#pragma once

#include <Eigen/Core>
#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/sim_truth.hpp"
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
  bool charger = false;  ///< `kind: charger`: the stripe that leads onto the charger
};

/// A shopping trolley (KUKA thesis ch. 15): a basket above laser height on four corner legs,
/// where the world file puts it. The simulation makes it a body that moves when pushed
/// (TrolleyBody); the exported map and pictures show its legs here.
struct Trolley {
  std::string id;  ///< `id:` in the file; "trolley-<n>" (1-based, in file order) without one
  Eigen::Vector2d center_m = Eigen::Vector2d::Zero();
  Eigen::Vector2d size_m = Eigen::Vector2d(0.9, 0.55);
  double yaw_rad = 0.0;
  double leg_radius_m = 0.02;

  Pose2 pose() const { return Pose2(center_m.x(), center_m.y(), yaw_rad); }
  /// The legs' centres in the trolley's frame (each inside a corner of its size).
  std::array<Eigen::Vector2d, 4> LegsInTrolley() const {
    const double hx = 0.5 * size_m.x() - leg_radius_m;
    const double hy = 0.5 * size_m.y() - leg_radius_m;
    return {Eigen::Vector2d(hx, hy), Eigen::Vector2d(hx, -hy), Eigen::Vector2d(-hx, hy),
            Eigen::Vector2d(-hx, -hy)};
  }
};

using ::fleetnav::FaultSpec;
using ::fleetnav::FaultType;
using ::fleetnav::FaultTypeByName;
using ::fleetnav::FaultTypeName;

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
  std::vector<Trolley> trolleys;
  std::vector<FaultSpec> faults;  ///< in force from the start of every run
};

/// Takes away what a remove_fence or remove_stripe fault removes: the parts of fences (cut
/// along their centre line) and of stripes inside the region. Other faults change nothing.
void ApplyGeometryFault(const FaultSpec& fault, WorldDescription* world);

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
///   trolleys:  [{id: t1, center: [x, y], size: [0.9, 0.55], yaw_deg: 0, leg_radius: 0.02}]
///   faults:    [{type: remove_fence, label: B, region: {min: [x, y], max: [x, y]},
///                robot: id, sensor: name, duration_s: 0, factor: 1}]
/// See docs/simulator.md.
/// Errors are InvalidArgument naming the list and index, e.g. "walls[2].to: expected [x, y]".
absl::StatusOr<WorldDescription> ParseWorldYaml(std::string_view yaml_text);
absl::StatusOr<WorldDescription> LoadWorld(const std::string& path);

}  // namespace fleetnav::sim
