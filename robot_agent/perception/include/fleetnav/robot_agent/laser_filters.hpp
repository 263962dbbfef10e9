#pragma once

#include <Eigen/Geometry>
#include <deque>
#include <vector>

#include "absl/status/status.h"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/sensor_frame.hpp"

namespace fleetnav::agent {

/// Per-beam median over the last `window` scans (the laser median filter of the KUKA thesis,
/// ch. 12): a thin trolley leg hit by one beam survives, where a median across neighbouring
/// beams would erase it, and range noise drops by about a third with 3 scans. A scan of a
/// different beam count restarts the window. Not thread-safe.
class TemporalMedianFilter {
 public:
  explicit TemporalMedianFilter(int window = 3) : window_(window < 1 ? 1 : window) {}
  LaserScanSample Apply(const LaserScanSample& scan);

 private:
  int window_;
  std::deque<std::vector<float>> history_;
};

/// Parameters of RemoveShadows: a pair of neighbouring returns whose connecting line meets the
/// nearer beam at less than `min_angle_rad` (or more than pi minus it) is a veiling "shadow"
/// between an edge and what lies behind it; the farther return of the pair is dropped.
struct ShadowFilterParams {
  double min_angle_rad = 0.17;  ///< about 10°
  int neighbours = 3;
  absl::Status Validate() const;
};

/// Drops (sets to NaN: no reading, neither a hit nor free space) the returns that end inside
/// `load_in_base`, the box of a load the robot carries: the legs of a latched trolley stand in
/// the laser's view wherever the robot goes and are not obstacles. Returns how many it dropped.
int MaskCarriedLoad(const Eigen::AlignedBox2d& load_in_base, const Pose2& laser_in_base,
                    LaserScanSample* scan);

/// The laser shadow filter (KUKA ch. 12): drops (sets to +infinity) the returns that veil the
/// edges of objects, such as the mixed pixels between a trolley leg and the shelf behind it.
LaserScanSample RemoveShadows(const LaserScanSample& scan, const ShadowFilterParams& params);

}  // namespace fleetnav::agent
