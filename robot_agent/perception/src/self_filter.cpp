#include "fleetnav/robot_agent/self_filter.hpp"

#include <Eigen/Geometry>

#include "fleetnav/robot_agent/laser_filters.hpp"

namespace fleetnav::agent {

void SelfFilter::Apply(const std::optional<Eigen::Vector2d>& carried_load_m,
                       SensorFrame* frame) const {
  if (!carried_load_m) return;
  const Eigen::Vector2d half = 0.5 * *carried_load_m + Eigen::Vector2d::Constant(margin_m_);
  const Eigen::AlignedBox2d load(-half, half);
  for (LaserScanSample& scan : frame->lasers) {
    if (const SensorMount* mount = model_.FindSensor(scan.name)) {
      MaskCarriedLoad(load, mount->pose_in_base, &scan);
    }
  }
}

}  // namespace fleetnav::agent
