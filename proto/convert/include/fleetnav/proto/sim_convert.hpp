#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/core/sim_truth.hpp"
#include "fleetnav/v1/sim_service.pb.h"

namespace fleetnav {

/// What the simulator says about its world (SimService.GetWorld), before it goes on the wire.
struct SimWorldSummary {
  /// One robot of the world: its kind's model (unset when its kind is unknown) and whether an
  /// agent is attached to it.
  struct Robot {
    std::string robot_id;
    std::optional<RobotModel> model;
    bool attached = false;
  };
  std::string world_name;
  double width_m = 0.0;
  double height_m = 0.0;
  double control_period_s = 0.0;
  double physics_step_s = 0.0;
  int64_t sim_time_ns = 0;
  std::vector<Robot> robots;
};

/// Wire <-> domain for the simulator's service: its world, its ground truth (with the calendar
/// at sim time 0; a min separation that is not finite, with fewer than two robots, goes as 1e9)
/// and the faults it is told to inject.
v1::GetWorldResponse ToProto(const SimWorldSummary& world);
v1::Twist2 ToProto(const Twist2& twist);
v1::GroundTruth ToProto(const GroundTruthSnapshot& truth, int64_t start_unix_ms);
v1::InjectFaultRequest ToProto(const FaultSpec& fault);
/// InvalidArgument naming `type` when it is unknown or unspecified, a region corner that is not
/// finite, and `factor` when a wheel slip has none; an unset factor (0) of the other faults
/// means 1.
absl::StatusOr<FaultSpec> FromProto(const v1::InjectFaultRequest& request);

}  // namespace fleetnav
