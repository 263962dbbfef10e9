#include "fleetnav/core/stripe_marker.hpp"

#include <cmath>
#include <unordered_map>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "fleetnav/core/angles.hpp"
#include "strings_internal.hpp"

namespace fleetnav {
namespace {

// Tolerances for a floor marker's quaternion (stripe_marker.hpp).
constexpr double kUnitNormTolerance = 1e-3;
constexpr double kTiltTolerance = 1e-3;

Eigen::Vector2d UnitDirection(const Line2& line) {
  const double norm = line.direction.norm();
  return norm > 0.0 ? Eigen::Vector2d(line.direction / norm) : Eigen::Vector2d::UnitX();
}

}  // namespace

Eigen::Vector2d FootPoint(const Line2& line, const Eigen::Vector2d& point) {
  const Eigen::Vector2d direction = UnitDirection(line);
  return line.point + direction * direction.dot(point - line.point);
}

double DistanceToLine(const Line2& line, const Eigen::Vector2d& point) {
  const Eigen::Vector2d direction = UnitDirection(line);
  const Eigen::Vector2d offset = point - line.point;
  return std::abs(direction.x() * offset.y() - direction.y() * offset.x());
}

Line2 StripeMarker::AsLine() const {
  return Line2{position_m, Eigen::Vector2d(std::cos(yaw_rad), std::sin(yaw_rad))};
}

Line2 StripeMarker::CalibrationLine(const Eigen::Vector2d& sensor_point_in_map) const {
  return Line2{sensor_point_in_map, Eigen::Vector2d(std::cos(yaw_rad), std::sin(yaw_rad))};
}

double NormalizeMarkerYaw(double yaw_rad) {
  if (!std::isfinite(yaw_rad)) return yaw_rad;
  // Shift so that the target range becomes [0, pi), wrap with period pi, shift back.
  double shifted = std::fmod(yaw_rad + kPi / 2.0, kPi);
  if (shifted < 0.0) shifted += kPi;
  if (shifted >= kPi) shifted -= kPi;
  return shifted - kPi / 2.0;
}

absl::StatusOr<double> YawFromQuaternion(double a, double b, double c, double d) {
  if (!std::isfinite(a) || !std::isfinite(b) || !std::isfinite(c) || !std::isfinite(d)) {
    return absl::InvalidArgumentError(
        absl::StrFormat("quaternion must be finite, got (%g, %g, %g, %g)", a, b, c, d));
  }
  const double norm = std::sqrt(a * a + b * b + c * c + d * d);
  if (std::abs(norm - 1.0) > kUnitNormTolerance) {
    return absl::InvalidArgumentError(
        absl::StrFormat("quaternion not of unit length (|q| = %g)", norm));
  }
  const double x = a / norm;
  const double y = b / norm;
  const double z = c / norm;
  const double w = d / norm;
  if (std::abs(x) >= kTiltTolerance || std::abs(y) >= kTiltTolerance) {
    return absl::InvalidArgumentError(absl::StrFormat(
        "quaternion tilts the marker out of the floor plane (a = %g, b = %g; both must be 0)", a,
        b));
  }
  const double yaw_rad = std::atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z));
  return NormalizeMarkerYaw(yaw_rad);
}

Eigen::Vector4d QuaternionFromYaw(double yaw_rad) {
  return {0.0, 0.0, std::sin(yaw_rad / 2.0), std::cos(yaw_rad / 2.0)};
}

absl::Status MarkerSet::Validate() const {
  std::unordered_map<int, size_t> index_by_id;
  for (size_t i = 0; i < markers.size(); ++i) {
    const StripeMarker& marker = markers[i];
    const std::string where = absl::StrCat("markers[", i, "] (id ", marker.id, ")");
    if (const auto [it, inserted] = index_by_id.emplace(marker.id, i); !inserted) {
      return absl::InvalidArgumentError(absl::StrCat("markers[", i, "]: duplicate id ", marker.id,
                                                     " (also markers[", it->second, "])"));
    }
    if (!marker.position_m.allFinite() || !std::isfinite(marker.z_m)) {
      return absl::InvalidArgumentError(absl::StrCat(where, ": position must be finite"));
    }
    if (!std::isfinite(marker.yaw_rad) || marker.yaw_rad < -kPi / 2.0 ||
        marker.yaw_rad >= kPi / 2.0) {
      return absl::InvalidArgumentError(
          absl::StrFormat("%s: yaw_rad must be in [-pi/2, pi/2), got %g", where, marker.yaw_rad));
    }
    if (!std::isfinite(marker.length_m) || marker.length_m <= 0.0) {
      return absl::InvalidArgumentError(
          absl::StrFormat("%s: length_m must be finite and > 0, got %g", where, marker.length_m));
    }
  }
  for (size_t i = 0; i < trolleys.size(); ++i) {
    const TrolleyPlacement& trolley = trolleys[i];
    const std::string where = absl::StrCat("trolleys[", i, "] (id '", trolley.id, "')");
    if (trolley.id.empty()) return absl::InvalidArgumentError(absl::StrCat(where, ": empty id"));
    for (size_t k = 0; k < i; ++k) {
      if (trolleys[k].id == trolley.id) {
        return absl::InvalidArgumentError(
            absl::StrCat(where, ": duplicate id (also trolleys[", k, "])"));
      }
    }
    if (!trolley.pose.IsFinite() || !trolley.size_m.allFinite() || trolley.size_m.minCoeff() <= 0 ||
        !(trolley.leg_radius_m > 0.0) || 2 * trolley.leg_radius_m >= trolley.size_m.minCoeff()) {
      return absl::InvalidArgumentError(absl::StrCat(
          where, ": pose must be finite, size > 0 and legs thinner than half the size"));
    }
  }
  return absl::OkStatus();
}

const TrolleyPlacement* MarkerSet::FindTrolley(const std::string& id) const {
  for (const TrolleyPlacement& trolley : trolleys) {
    if (trolley.id == id) return &trolley;
  }
  return nullptr;
}

const StripeMarker* MarkerSet::Find(int id) const {
  for (const StripeMarker& marker : markers) {
    if (marker.id == id) return &marker;
  }
  return nullptr;
}

std::vector<const StripeMarker*> MarkerSet::Within(const Eigen::Vector2d& point_in_map,
                                                   double distance_m) const {
  std::vector<const StripeMarker*> found;
  for (const StripeMarker& marker : markers) {
    if ((marker.position_m - point_in_map).norm() <= distance_m) found.push_back(&marker);
  }
  return found;
}

std::string_view MarkerKindName(MarkerKind kind) {
  switch (kind) {
    case MarkerKind::kCalibration:
      return "calibration";
    case MarkerKind::kFollowStripe:
      return "follow_stripe";
    case MarkerKind::kChargerStripe:
      return "charger_stripe";
  }
  return "calibration";
}

absl::StatusOr<MarkerKind> ParseMarkerKind(std::string_view name) {
  for (MarkerKind kind :
       {MarkerKind::kCalibration, MarkerKind::kFollowStripe, MarkerKind::kChargerStripe}) {
    if (name == MarkerKindName(kind)) return kind;
  }
  return absl::InvalidArgumentError(
      absl::StrCat("unknown marker kind '", internal::ToAbsl(name),
                   "' (expected calibration, follow_stripe or charger_stripe)"));
}

}  // namespace fleetnav
