#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "absl/status/status.h"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/core/sensor_frame.hpp"
#include "fleetnav/robot_agent/laser_filters.hpp"

namespace fleetnav::agent {

/// What a trolley looks like to the laser and how it is docked under (KUKA thesis ch. 14–15):
/// four legs at the corners of a rectangle `leg_spacing_x_m` × `leg_spacing_y_m` (leg centre
/// to leg centre), each a circle of `leg_radius_m`. Defaults: the store's 1.0 × 0.7 m trolleys
/// with Ø 4 cm legs.
struct TrolleySpec {
  double leg_spacing_x_m = 0.96;
  double leg_spacing_y_m = 0.66;
  double leg_radius_m = 0.02;
  /// A leg distance matches when within this of the spec.
  double spacing_tolerance_m = 0.05;
  /// Clustering gap and the extent a leg's cluster may have.
  double cluster_gap_m = 0.06;
  double max_leg_extent_m = 0.08;
  ShadowFilterParams shadow;
  absl::Status Validate() const;
};

/// A trolley found in a scan, in base_link: its centre and the direction of its x axis (along
/// `leg_spacing_x_m`, pointing away from the robot), and the legs seen (3 or 4).
struct TrolleyDetection {
  Pose2 pose_in_base;
  int legs_seen = 0;
};

/// Leg candidates of a (filtered) scan in base_link: clusters no wider than
/// `max_leg_extent_m` that the iterative end-point fit does not find to be a wall, fitted with a
/// circle of the leg radius (KUKA ch. 13).
std::vector<Eigen::Vector2d> LegCandidates(const LaserScanSample& scan, const Pose2& laser_in_base,
                                           const TrolleySpec& spec);

/// Trolleys among leg candidates (KUKA ch. 14, "trolley recognition from leg distances"): three
/// legs whose two distances from a corner leg match the spacings at a right angle make a
/// trolley; a fourth at the predicted corner is counted. Sorted nearest first.
std::vector<TrolleyDetection> RecognizeTrolleys(const std::vector<Eigen::Vector2d>& legs,
                                                const TrolleySpec& spec);

/// The way out from under a trolley just set down (base_link): through the middle of the two
/// legs ahead, along the normal of the line between them.
struct LegGate {
  Eigen::Vector2d middle_m;
  Eigen::Vector2d direction;  ///< unit, away from the robot's centre
};

/// Leg candidates round a robot standing under a trolley (base_link): the clusters within the
/// trolley's half-diagonal and 15 cm of the robot's centre no wider than `max_leg_extent_m`, fitted
/// with a circle of the leg radius. Without LegCandidates' wall test: nothing but the trolley's
/// legs stands that near, and at a third of a metre the noise bends a leg's arc into several
/// segments, so the test dropped one leg of the pair in two.
std::vector<Eigen::Vector2d> LegsAround(const LaserScanSample& scan, const Pose2& laser_in_base,
                                        const TrolleySpec& spec);

/// The pair of leg candidates a robot standing under a trolley leaves between when it moves in
/// `move_direction` (base_link, unit): two legs a side's spacing apart (either side of the
/// trolley, within the spec's tolerance), ahead of the robot's centre and within the trolley's
/// half-diagonal and 15 cm of it, whose middle lies within `max_offset_m` of the move's line and
/// whose normal is within `max_angle_rad` of the move. The best-centred pair; nullopt when none.
std::optional<LegGate> FindLegGate(const std::vector<Eigen::Vector2d>& legs,
                                   const Eigen::Vector2d& move_direction, const TrolleySpec& spec,
                                   double max_offset_m, double max_angle_rad);

/// Dock frames of a trolley for a robot (KUKA ch. 15): `approach` stands `standoff_m` in front
/// of the trolley's near end, facing along its x axis; `final` is under its centre, same yaw.
struct DockFrames {
  Pose2 approach;
  Pose2 final;
};
DockFrames DockFramesFor(const Pose2& trolley, const TrolleySpec& spec, const RobotModel& model,
                         double standoff_m);

}  // namespace fleetnav::agent
