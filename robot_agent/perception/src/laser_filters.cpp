#include "fleetnav/robot_agent/laser_filters.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "fleetnav/core/angles.hpp"

namespace fleetnav::agent {

LaserScanSample TemporalMedianFilter::Apply(const LaserScanSample& scan) {
  if (!history_.empty() && history_.front().size() != scan.ranges_m.size()) history_.clear();
  history_.push_back(scan.ranges_m);
  while (static_cast<int>(history_.size()) > window_) history_.pop_front();
  LaserScanSample out = scan;
  std::vector<float> values(history_.size());
  for (size_t beam = 0; beam < scan.ranges_m.size(); ++beam) {
    for (size_t k = 0; k < history_.size(); ++k) values[k] = history_[k][beam];
    std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
    out.ranges_m[beam] = values[values.size() / 2];
  }
  return out;
}

absl::Status ShadowFilterParams::Validate() const {
  if (!(min_angle_rad > 0.0 && min_angle_rad < (kPi / 2))) {
    return absl::InvalidArgumentError("shadow.min_angle_rad: must be in (0, pi/2)");
  }
  if (neighbours < 1) return absl::InvalidArgumentError("shadow.neighbours: must be >= 1");
  return absl::OkStatus();
}

LaserScanSample RemoveShadows(const LaserScanSample& scan, const ShadowFilterParams& params) {
  LaserScanSample out = scan;
  const auto valid = [&](float r) { return std::isfinite(r) && r > 0.0f && r < scan.range_max_m; };
  const size_t n = scan.ranges_m.size();
  for (size_t i = 0; i < n; ++i) {
    if (!valid(scan.ranges_m[i])) continue;
    for (size_t j = i + 1; j < std::min(n, i + 1 + static_cast<size_t>(params.neighbours)); ++j) {
      if (!valid(scan.ranges_m[j])) continue;
      const double ri = scan.ranges_m[i], rj = scan.ranges_m[j];
      const double dtheta = static_cast<double>(j - i) * scan.angle_increment_rad;
      // The angle at the nearer return between its beam and the line to the other return.
      const double near = std::min(ri, rj), far = std::max(ri, rj);
      const double angle = std::atan2(far * std::sin(dtheta), far * std::cos(dtheta) - near);
      const double seen = std::abs(angle);
      if (seen < params.min_angle_rad || seen > kPi - params.min_angle_rad) {
        out.ranges_m[ri > rj ? i : j] = std::numeric_limits<float>::infinity();
      }
    }
  }
  return out;
}

int MaskCarriedLoad(const Eigen::AlignedBox2d& load_in_base, const Pose2& laser_in_base,
                    LaserScanSample* scan) {
  int dropped = 0;
  for (size_t i = 0; i < scan->ranges_m.size(); ++i) {
    const double r = scan->ranges_m[i];
    if (!std::isfinite(r) || r >= scan->range_max_m) continue;
    const double angle = scan->angle_min_rad + static_cast<double>(i) * scan->angle_increment_rad;
    const Eigen::Vector2d end =
        laser_in_base.TransformPoint(Eigen::Vector2d(r * std::cos(angle), r * std::sin(angle)));
    if (load_in_base.contains(end)) {
      scan->ranges_m[i] = std::numeric_limits<float>::quiet_NaN();
      ++dropped;
    }
  }
  return dropped;
}

}  // namespace fleetnav::agent
