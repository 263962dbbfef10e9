#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "absl/status/status.h"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/sensor_frame.hpp"

namespace fleetnav::agent {

/// The finite returns of a scan as points in base_link, in beam order.
std::vector<Eigen::Vector2d> ScanPoints(const LaserScanSample& scan, const Pose2& laser_in_base);

/// Breaks a beam-ordered point list into clusters wherever two consecutive points are more than
/// `max_gap_m` apart (KUKA ch. 13, "clustering").
std::vector<std::vector<Eigen::Vector2d>> ClusterPoints(const std::vector<Eigen::Vector2d>& points,
                                                        double max_gap_m);

/// A straight line segment from a cluster.
struct LineSegment {
  Eigen::Vector2d from;
  Eigen::Vector2d to;
  double length_m() const { return (to - from).norm(); }
};

/// Iterative end-point fit (split and merge, KUKA ch. 13): a cluster is split at the point
/// farthest from the chord between its ends while that point is more than `split_distance_m`
/// off it; then neighbouring segments whose directions differ by less than `merge_angle_rad`
/// are merged again.
std::vector<LineSegment> IterativeEndPointFit(const std::vector<Eigen::Vector2d>& cluster,
                                              double split_distance_m, double merge_angle_rad);

/// A circle found in a cluster.
struct Circle {
  Eigen::Vector2d center_m;
  double radius_m = 0.0;
  double rms_error_m = 0.0;
};

/// The circle of known `radius_m` (a trolley leg) that best fits a cluster seen from
/// `viewpoint` (least squares on the centre, Gauss–Newton from the centroid pushed one radius
/// away from the viewpoint; KUKA ch. 13, "circle extraction"). nullopt for an empty cluster.
std::optional<Circle> FitCircleOfRadius(const std::vector<Eigen::Vector2d>& cluster,
                                        double radius_m, const Eigen::Vector2d& viewpoint);

}  // namespace fleetnav::agent
