#pragma once

#include <Eigen/Core>
#include <optional>

#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/core/sensor_frame.hpp"

namespace fleetnav::agent {

/// Takes what the robot carries out of its own sensor frames before anything reads them (the
/// localizer first): the legs of a trolley latched on the lift ride along in every laser's
/// view and are neither obstacles nor landmarks. Returns that end within the load's box (grown
/// by `margin_m`: the legs stand at its corners) are dropped. Value type.
class SelfFilter {
 public:
  SelfFilter(RobotModel model, double margin_m) : model_(std::move(model)), margin_m_(margin_m) {}

  /// Drops the returns of `carried_load_m` (length, width; nullopt: nothing carried) from
  /// every laser of `frame`.
  void Apply(const std::optional<Eigen::Vector2d>& carried_load_m, SensorFrame* frame) const;

 private:
  RobotModel model_;
  double margin_m_;
};

}  // namespace fleetnav::agent
