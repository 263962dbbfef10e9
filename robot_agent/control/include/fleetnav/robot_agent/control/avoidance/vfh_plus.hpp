#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "absl/status/status.h"

namespace fleetnav::agent {

struct VfhPlusParams {
  /// Angular width of one histogram sector (α).
  double sector_rad = 0.0436;  // 2.5°
  /// Obstacle points farther than this from the robot are not looked at (the active window).
  double window_radius_m = 2.5;
  /// The robot as a circle of this radius (r_r), enlarged by the safety distance (d_s).
  double robot_radius_m = 0.30;
  double safety_distance_m = 0.10;
  /// Binary histogram thresholds, as distances of an enlarged obstacle: a sector is blocked
  /// when one is nearer than blocked_within_m, free again when none is nearer than
  /// free_beyond_m, and keeps its state in between (the hysteresis τ_high / τ_low).
  double blocked_within_m = 2.0;
  double free_beyond_m = 2.3;
  /// The radius of the tightest circle the robot can drive (its turning circles, for masking).
  double min_turning_radius_m = 1.1;
  /// Directions beyond ± this off the heading are not candidates (a car does not drive
  /// sideways; the laser does not see behind).
  double max_direction_rad = 1.5708;
  /// A valley wider than this many sectors is wide (s_max); in a wide one the robot keeps
  /// s_max / 2 sectors off its border (10° here: a car swerves no more than it must).
  int wide_valley_sectors = 8;
  /// Cost weights (μ1 > μ2 + μ3 for goal-oriented behaviour).
  double target_weight = 5.0;
  double heading_weight = 2.0;
  double previous_weight = 2.0;
  absl::Status Validate() const;
};

/// The direction VFH+ chose, in the robot frame (0 = ahead, positive left), and the
/// enlarged-obstacle clearance along it (window_radius_m when nothing is near it).
struct VfhPlusDirection {
  double direction_rad = 0.0;
  double clearance_m = 0.0;
};

/// The Vector Field Histogram+ (Ulrich & Borenstein, "VFH+: Reliable Obstacle Avoidance for Fast
/// Mobile Robots", ICRA 1998) on laser points in the robot frame. Each point within the active
/// window adds the magnitude m = w² − d² (certainty 1) to every sector within its enlargement
/// angle γ = asin((r_r + d_s) / d) — the primary histogram takes each sector's largest magnitude,
/// so a denser laser does not block more; a binary histogram with two thresholds and memory
/// (hysteresis) follows; the masked histogram also blocks every direction the robot cannot
/// reach without its turning circles (centres at (0, ±R) for base_link on the rear axle) meeting
/// an enlarged obstacle; candidate directions are the centres of narrow valleys and, in wide
/// valleys, the borders' inner points and the target if it lies between them; the cheapest by
/// μ1·Δ(target) + μ2·Δ(heading) + μ3·Δ(previous choice) wins. Keeps the binary histogram and
/// the previous choice between calls. Not thread-safe.
class VfhPlus {
 public:
  explicit VfhPlus(VfhPlusParams params);

  /// Chooses a direction towards `target_rad` (robot frame) among `points` (robot frame);
  /// nullopt when every direction within ±max_direction_rad is blocked.
  std::optional<VfhPlusDirection> Choose(const std::vector<Eigen::Vector2d>& points,
                                         double target_rad);

 private:
  /// Sector k (any integer) is centred on k · sector_width_rad_; index into the histograms.
  int IndexOf(int k) const;

  VfhPlusParams params_;
  double sector_width_rad_ = 0.0;
  std::vector<bool> binary_;
  /// The previous choice, in sectors off the heading.
  std::optional<double> previous_k_;
};

}  // namespace fleetnav::agent
