#include "fleetnav/robot_agent/control/avoidance/vfh_plus.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "fleetnav/core/angles.hpp"

namespace fleetnav::agent {

absl::Status VfhPlusParams::Validate() const {
  for (double v : {sector_rad, window_radius_m, robot_radius_m, min_turning_radius_m,
                   max_direction_rad, blocked_within_m, free_beyond_m}) {
    if (!(std::isfinite(v) && v > 0.0)) {
      return absl::InvalidArgumentError("VFH+ parameters: distances and angles must be > 0");
    }
  }
  if (!(std::isfinite(safety_distance_m) && safety_distance_m >= 0.0)) {
    return absl::InvalidArgumentError("VFH+ safety_distance_m: must be >= 0");
  }
  if (!(blocked_within_m <= free_beyond_m && free_beyond_m <= window_radius_m)) {
    return absl::InvalidArgumentError(
        "VFH+ thresholds: blocked_within_m <= free_beyond_m <= window_radius_m required");
  }
  if (sector_rad > kPi / 4.0 || max_direction_rad > kPi - sector_rad) {
    return absl::InvalidArgumentError(
        "VFH+: sector_rad <= pi/4 and max_direction_rad < pi - sector_rad required");
  }
  if (wide_valley_sectors < 2 || !(target_weight > heading_weight + previous_weight) ||
      heading_weight < 0.0 || previous_weight < 0.0) {
    return absl::InvalidArgumentError(
        "VFH+: wide_valley_sectors >= 2 and target_weight > heading_weight + previous_weight "
        ">= 0 required");
  }
  return absl::OkStatus();
}

VfhPlus::VfhPlus(VfhPlusParams params) : params_(params) {
  const int count = std::max(8, static_cast<int>(std::lround(2.0 * kPi / params_.sector_rad)));
  sector_width_rad_ = 2.0 * kPi / count;
  binary_.assign(count, false);
}

int VfhPlus::IndexOf(int k) const {
  const int n = static_cast<int>(binary_.size());
  return ((k % n) + n) % n;
}

std::optional<VfhPlusDirection> VfhPlus::Choose(const std::vector<Eigen::Vector2d>& points,
                                                double target_rad) {
  const int n = static_cast<int>(binary_.size());
  const double window_sq = params_.window_radius_m * params_.window_radius_m;
  const double enlarged_m = params_.robot_radius_m + params_.safety_distance_m;
  const double turning_m = params_.min_turning_radius_m;
  // 1. Primary polar histogram: the largest magnitude per sector.
  std::vector<double> primary(n, 0.0);
  // 3. (gathered in the same pass) the directions the turning circles leave reachable.
  double right_limit_rad = -kPi;
  double left_limit_rad = kPi;
  for (const Eigen::Vector2d& p : points) {
    const double d_sq = p.squaredNorm();
    if (!(d_sq <= window_sq) || d_sq < 1e-12) continue;
    const double d = std::sqrt(d_sq);
    const double bearing = std::atan2(p.y(), p.x());
    const double gamma = d <= enlarged_m ? kPi / 2.0 : std::asin(enlarged_m / d);
    const double magnitude = window_sq - d_sq;
    const int k_lo = static_cast<int>(std::ceil((bearing - gamma) / sector_width_rad_));
    const int k_hi = static_cast<int>(std::floor((bearing + gamma) / sector_width_rad_));
    for (int k = k_lo; k <= k_hi; ++k) {
      double& h = primary[IndexOf(k)];
      h = std::max(h, magnitude);
    }
    const double reach_sq = (turning_m + enlarged_m) * (turning_m + enlarged_m);
    if (p.y() < 0.0) {
      if ((p - Eigen::Vector2d(0.0, -turning_m)).squaredNorm() < reach_sq) {
        right_limit_rad = std::max(right_limit_rad, bearing);
      }
    } else if ((p - Eigen::Vector2d(0.0, turning_m)).squaredNorm() < reach_sq) {
      left_limit_rad = std::min(left_limit_rad, bearing);
    }
  }
  // 2. Binary histogram with hysteresis.
  const double high = window_sq - params_.blocked_within_m * params_.blocked_within_m;
  const double low = window_sq - params_.free_beyond_m * params_.free_beyond_m;
  for (int i = 0; i < n; ++i) {
    if (primary[i] > high) {
      binary_[i] = true;
    } else if (primary[i] < low) {
      binary_[i] = false;
    }
  }
  // 3. Masked histogram over the candidate range, 4. valleys and their candidate directions.
  const int k_max = static_cast<int>(std::floor(params_.max_direction_rad / sector_width_rad_));
  const auto open = [&](int k) {
    const double angle = k * sector_width_rad_;
    return !binary_[IndexOf(k)] && angle >= right_limit_rad && angle <= left_limit_rad;
  };
  const double target_k = NormalizeAngle(target_rad) / sector_width_rad_;
  const double half_wide = params_.wide_valley_sectors / 2.0;
  std::vector<double> candidates;
  for (int k = -k_max; k <= k_max; ++k) {
    if (!open(k)) continue;
    const int right = k;
    while (k + 1 <= k_max && open(k + 1)) ++k;
    const int left = k;
    if (left - right + 1 > params_.wide_valley_sectors) {
      const double inner_right = right + half_wide;
      const double inner_left = left - half_wide;
      candidates.push_back(inner_right);
      candidates.push_back(inner_left);
      if (target_k > inner_right && target_k < inner_left) candidates.push_back(target_k);
    } else {
      candidates.push_back(0.5 * (right + left));
    }
  }
  if (candidates.empty()) {
    previous_k_.reset();
    return std::nullopt;
  }
  // 5. The cheapest candidate.
  double best_k = candidates.front();
  double best_cost = std::numeric_limits<double>::infinity();
  for (double c : candidates) {
    const double cost = params_.target_weight * std::abs(c - target_k) +
                        params_.heading_weight * std::abs(c) +
                        params_.previous_weight * std::abs(c - previous_k_.value_or(target_k));
    if (cost < best_cost) {
      best_cost = cost;
      best_k = c;
    }
  }
  previous_k_ = best_k;
  const double h = primary[IndexOf(static_cast<int>(std::lround(best_k)))];
  return VfhPlusDirection{best_k * sector_width_rad_, std::sqrt(std::max(window_sq - h, 0.0))};
}

}  // namespace fleetnav::agent
