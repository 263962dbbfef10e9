#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <string>
#include <utility>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/core/stripe_marker.hpp"
#include "fleetnav/localization/amcl.hpp"

namespace fleetnav::localization {

enum class SamclMode {
  kHard,  ///< thesis Algorithm 4: move every particle onto the calibration line
  kSoft,  ///< reweight particles by their sensor point's distance to the marker line
};

/// Parameters of SAMCL.
struct SamclParams {
  SamclMode mode = SamclMode::kHard;
  /// h of Algorithm 4: a marker is associated when the estimated sensor point is within this
  /// distance of the marker's position.
  double association_radius_m = 1.0;
  /// With no marker within association_radius_m (wheel slip ran the estimate further along),
  /// the nearest marker within this distance is still associated when it is unambiguous: every
  /// other marker at least twice as far, and no stripe crossing the travel (whose edge the
  /// sensor may have felt) that near. 0 disables.
  double far_association_radius_m = 0.0;
  /// A marker is associated only when the robot crosses it at least this steeply (markers lie
  /// across the travel; a stripe crossed near one is not the marker).
  double min_crossing_angle_rad = 0.5;
  /// Half the marker strip's width: the detection edge is its near edge, not its centre line
  /// (0 for an edge stamped on the centre line, as the synthetic experiment does).
  double marker_half_width_m = 0.0;
  /// Soft mode: standard deviation of the sensor point's distance to the marker line.
  double soft_sigma_m = 0.02;
  /// Stripe pieces of the marker set (follow and charger stripes) are metal too. An edge is
  /// the marker's only when the marker explains it decisively better than every stripe piece
  /// near it: by the squared Mahalanobis distance from the estimated sensor point of where the
  /// sensor's path meets the piece (the estimate's covariance carried to the sensor, plus
  /// feature_sigma_m on each axis),
  /// which must exceed the marker's by at least decisive_mahalanobis2 (6 ≈ 2 ln 20: the marker
  /// 20 times as likely). Otherwise nothing is calibrated (CalibrationOutcome::kStripe).
  double feature_sigma_m = 0.03;
  double decisive_mahalanobis2 = 6.0;
  /// A stripe piece that the same sensor's previous edge, no further back than this much
  /// travel, already felt (where it lies if this edge is the marker) is no rival: crossing a
  /// stripe's end and then the marker just beyond it are two edges, one feature each.
  double edge_memory_m = 3.0;
  /// Odometry history kept to interpolate the pose at a detection edge.
  double odometry_history_s = 5.0;
  /// Edges older than the history (or in the future) are refused as OutOfRange.
  absl::Status Validate() const;
};

/// An inductive detection edge: the moment `sensor_name` first saw metal, stamped by the
/// sensor driver (not by the time it reached the filter).
struct InductiveEdge {
  std::string sensor_name;
  int64_t stamp_ns = 0;
};

enum class CalibrationOutcome {
  kApplied,
  kNoMarker,
  kAmbiguous,  ///< two markers within h
  kStripe,     ///< a stripe piece near the marker explains the edge as well as the marker
};

struct CalibrationResult {
  CalibrationOutcome outcome = CalibrationOutcome::kNoMarker;
  int marker_id = -1;
  /// Mean shift applied to the particles (hard) or the estimate's move (soft), metres.
  double correction_m = 0.0;
};

/// Stripe-marker AMCL (Lely thesis §5.4, Algorithm 4): AMCL plus, on an inductive detection,
/// (1) the marker within h of the estimate is associated — none, or two or more, and nothing
/// is done (an ambiguous association is refused rather than guessed), nor when a stripe piece
/// of the marker set explains the edge about as well, given the estimate's covariance; (2) odometry
/// is interpolated to the stamped detection edge, so that filter latency does not put the line
/// late; (3) hard mode: every particle is shifted so that its own detecting-sensor point lands
/// on its foot point on the marker line — the calibration line of §5.4.2 step 2 for that
/// particle — keeping its weight and yaw; soft mode: each particle's weight is multiplied by
/// N(d; 0, soft_sigma) of that distance, then resampled if N_eff is low. Not thread-safe.
class Samcl {
 public:
  static absl::StatusOr<Samcl> Create(Amcl amcl, MarkerSet markers, RobotModel model,
                                      const SamclParams& params);

  /// AMCL update; also records the odometry for edge interpolation.
  absl::StatusOr<bool> Update(const Pose2& pose_in_odom, const RangeObservation& observation,
                              int64_t stamp_ns);
  /// Records odometry without a filter update (call every tick).
  void RecordOdometry(const Pose2& pose_in_odom, int64_t stamp_ns);
  /// Applies a detection edge. The newest recorded odometry is the "now" of the correction.
  absl::StatusOr<CalibrationResult> OnInductiveEdge(const InductiveEdge& edge);

  /// Odometry interpolated at stamp_ns from the history, or OutOfRange.
  absl::StatusOr<Pose2> OdometryAt(int64_t stamp_ns) const;

  Amcl& amcl() { return amcl_; }
  const Amcl& amcl() const { return amcl_; }
  const SamclParams& params() const { return params_; }

 private:
  Samcl(Amcl amcl, MarkerSet markers, RobotModel model, const SamclParams& params)
      : amcl_(std::move(amcl)),
        markers_(std::move(markers)),
        model_(std::move(model)),
        params_(params) {}

  /// The marker far association picks for an edge felt at `sensor_estimate` (see
  /// SamclParams::far_association_radius_m), or nullptr.
  const StripeMarker* FarMarker(const Eigen::Vector2d& sensor_estimate,
                                const Eigen::Vector2d& heading) const;
  /// A stripe piece that explains an edge felt by `mount` at the odometry pose `odom_at_edge`
  /// about as well as `marker` does (SamclParams::decisive_mahalanobis2), or nullptr.
  const StripeMarker* RivalStripe(const StripeMarker& marker, const SensorMount& mount,
                                  const std::string& sensor_name, const Pose2& odom_at_edge) const;

  Amcl amcl_;
  MarkerSet markers_;
  RobotModel model_;
  SamclParams params_;
  std::deque<std::pair<int64_t, Pose2>> odometry_;
  /// Per inductive sensor, the odometry pose of its last edge.
  std::map<std::string, Pose2> last_edge_odom_;
};

}  // namespace fleetnav::localization
