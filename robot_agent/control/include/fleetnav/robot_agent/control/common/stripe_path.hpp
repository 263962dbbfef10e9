#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "fleetnav/core/stripe_marker.hpp"

namespace fleetnav::agent {

/// The floor stripe a stripe leg follows, as the inductive sensor meets it: the marker set's
/// straight pieces of the leg's stripe and of every stripe joined to it end to end (a straight,
/// a quarter-circle arc, the next straight: Lely thesis Fig. 1.3), chained into one polyline.
/// It gives the map-based fallback its line through an interruption, the feed-forward yaw rate
/// of the curves (the pieces' turning per metre) and the stripe's real ends (a joint between
/// two stripes is not an end). Where pieces branch (three or more meet), only the leg's own
/// stripe is chained. Points are projected near where the last projection fell, so a path that
/// curves back on itself is followed in order. Value type; not thread-safe.
class StripePath {
 public:
  /// Chains the pieces of stripe `stripe_id` among `pieces` (follow or charger stripes of one
  /// kind) with the stripes joined to them; nullopt when the stripe has no pieces.
  static std::optional<StripePath> Build(const std::vector<StripeMarker>& pieces, int stripe_id);

  /// Where a point projects onto the path.
  struct Foot {
    double s_m = 0.0;  ///< arc length from the first vertex
    Eigen::Vector2d point = Eigen::Vector2d::Zero();
    Eigen::Vector2d tangent = Eigen::Vector2d::UnitX();  ///< unit, in the path's direction
    double curvature_per_m = 0.0;                        ///< positive: turning left
    double distance_m = 0.0;                             ///< from the point to the foot
  };

  /// Reverses the path if needed so that it runs along `heading` at the foot of `point`, and
  /// makes that foot the start of the next projections' search.
  void OrientAlong(const Eigen::Vector2d& point, const Eigen::Vector2d& heading);
  /// Projects `point` onto the part of the path within `window_m` of the last foot (the whole
  /// path the first time) and remembers the foot.
  Foot Project(const Eigen::Vector2d& point, double window_m = 1.0);
  /// The largest |curvature| over [s_m, s_m + ahead_m].
  double MaxCurvatureAhead(double s_m, double ahead_m) const;

  double length_m() const { return cumulative_m_.back(); }
  const std::vector<Eigen::Vector2d>& vertices() const { return vertices_; }
  /// The path's two ends: where the stripe physically ends.
  Eigen::Vector2d front() const { return vertices_.front(); }
  Eigen::Vector2d back() const { return vertices_.back(); }

 private:
  explicit StripePath(std::vector<Eigen::Vector2d> vertices);
  void Measure();
  Foot FootOnSegment(size_t segment, const Eigen::Vector2d& point) const;

  std::vector<Eigen::Vector2d> vertices_;
  std::vector<double> cumulative_m_;     ///< arc length at each vertex
  std::vector<double> curvature_per_m_;  ///< per segment
  std::optional<double> last_s_m_;
};

}  // namespace fleetnav::agent
