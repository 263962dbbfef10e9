#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/core/pose2.hpp"

namespace fleetnav {

enum class MarkerKind { kCalibration, kFollowStripe, kChargerStripe };

/// A straight line in the map plane: a point on it and a unit direction.
struct Line2 {
  Eigen::Vector2d point = Eigen::Vector2d::Zero();
  Eigen::Vector2d direction = Eigen::Vector2d::UnitX();  ///< unit length
};

/// Foot point of `point` on `line`: the orthogonal projection (Lely thesis §5.4.2, step 3).
Eigen::Vector2d FootPoint(const Line2& line, const Eigen::Vector2d& point);
/// Unsigned distance from a point to a line.
double DistanceToLine(const Line2& line, const Eigen::Vector2d& point);

/// A metal stripe on the floor at a known pose (Lely thesis §5.4.1). The stored form is the
/// thesis's: a point on the marker (x, y, z) and an orientation quaternion (a, b, c, d) =
/// (x, y, z, w) about the vertical axis. A stripe has no direction, so the yaw is kept in the
/// thesis's range [-pi/2, pi/2). length_m is the stripe's extent along its yaw, centred on the
/// point. Value type.
struct StripeMarker {
  int id = 0;
  Eigen::Vector2d position_m = Eigen::Vector2d::Zero();
  double z_m = 0.0;
  double yaw_rad = 0.0;  ///< in [-pi/2, pi/2)
  double length_m = 0.5;
  MarkerKind kind = MarkerKind::kCalibration;
  /// Follow and charger stripes: the stripe this straight piece belongs to (routes name
  /// stripes by it; a curved stripe is several pieces). 0: none.
  int stripe_id = 0;

  /// The marker as a line (thesis eq. 5.7–5.9).
  Line2 AsLine() const;
  /// The calibration line: through the point where the inductive sensor crossed the marker
  /// and parallel to the marker (thesis §5.4.2 step 2).
  Line2 CalibrationLine(const Eigen::Vector2d& sensor_point_in_map) const;
};

/// Wraps any yaw to the marker range [-pi/2, pi/2) (a line at yaw and yaw+pi is the same).
double NormalizeMarkerYaw(double yaw_rad);

/// Converts a unit quaternion (a, b, c, d) = (x, y, z, w) of a floor marker to yaw. Refuses a
/// quaternion that is not of unit length (|q| off by more than 1e-3) or that tilts the marker
/// out of the floor plane, with InvalidArgument.
absl::StatusOr<double> YawFromQuaternion(double a, double b, double c, double d);
/// The quaternion (a, b, c, d) of a yaw rotation about z.
Eigen::Vector4d QuaternionFromYaw(double yaw_rad);

/// A trolley standing on the site (KUKA thesis ch. 15) that robots dock under: its id for dock
/// actions, where it stood when the map was made, its outer size and its legs' radius.
struct TrolleyPlacement {
  std::string id;
  Pose2 pose;
  Eigen::Vector2d size_m = Eigen::Vector2d(1.0, 0.7);
  double leg_radius_m = 0.02;
};

/// All stripe markers of one map, with unique ids, and the trolleys standing on it. Validate()
/// checks ids unique, positions finite, lengths > 0.
struct MarkerSet {
  std::string map_id;
  std::vector<StripeMarker> markers;
  std::vector<TrolleyPlacement> trolleys;
  const TrolleyPlacement* FindTrolley(const std::string& id) const;

  absl::Status Validate() const;
  const StripeMarker* Find(int id) const;
  /// Markers whose position lies within distance_m of point_in_map.
  std::vector<const StripeMarker*> Within(const Eigen::Vector2d& point_in_map,
                                          double distance_m) const;
};

/// Marker YAML in the thesis's form:
///   markers:
///     - id: 1
///       position: {x: 0.0, y: 4.7, z: 0.0}
///       orientation: {a: 0.0, b: 0.0, c: 0.7071, d: 0.7071}
///       length: 0.5          # optional, metres
///       kind: calibration    # optional: calibration | follow_stripe | charger_stripe
///   trolleys:                # optional
///     - {id: trolley-1, pose: [x, y, yaw_deg], size: [1.0, 0.7], leg_radius: 0.02}
absl::StatusOr<MarkerSet> ParseMarkerSetYaml(std::string_view yaml_text);
std::string MarkerSetToYaml(const MarkerSet& markers);
absl::StatusOr<MarkerSet> LoadMarkerSet(const std::string& path);
absl::Status SaveMarkerSet(const MarkerSet& markers, const std::string& path);

std::string_view MarkerKindName(MarkerKind kind);
absl::StatusOr<MarkerKind> ParseMarkerKind(std::string_view name);

}  // namespace fleetnav
