#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "fleetnav/core/sensor_frame.hpp"
#include "fleetnav/sim/diff_drive_robot.hpp"
#include "fleetnav/sim/ode_world.hpp"
#include "fleetnav/sim/proprioceptive_sensors.hpp"
#include "fleetnav/sim/world_description.hpp"

namespace fleetnav::sim {

struct SimulationParams {
  double physics_step_s = 0.002;    ///< ≤ 5 ms keeps the heavy robot's yaw tracking ≥ 95 %
  double control_period_s = 0.02;   ///< one lockstep tick (50 Hz)
  uint64_t seed = 1;
  ProprioceptiveParams sensors;
  /// Checks positive steps and that the control period is a whole number of physics steps.
  absl::Status Validate() const;
};

struct RobotTruth {
  std::string robot_id;
  Pose2 pose;
  Twist2 velocity;
  double up_z = 1.0;
};

struct SimContact {
  std::string robot_id;
  std::string other;  ///< another robot's id, or "static"
  int64_t sim_time_ns = 0;
};

struct GroundTruthSnapshot {
  uint64_t tick = 0;
  int64_t sim_time_ns = 0;
  std::vector<RobotTruth> robots;
  std::vector<SimContact> contacts;
  /// Smallest distance between two robots' circumscribed circles so far (a lower bound on the
  /// footprint distance); +inf with fewer than two robots.
  double min_separation_m = 0.0;
};

/// One simulated site: the ODE world of a WorldDescription and its robots, advanced in fixed
/// control ticks of whole physics steps. The tick counter is the only clock of a simulated run
/// (sim time = tick × control period). Deterministic for a seed. Not thread-safe: the lockstep
/// coordinator serialises access.
class Simulation {
 public:
  static absl::StatusOr<std::unique_ptr<Simulation>> Create(const WorldDescription& world,
                                                             SimulationParams params);

  /// Adds a robot of a preset kind; AlreadyExists for a duplicate id, NotFound for an unknown
  /// kind, Unimplemented for a kinematics this version cannot simulate yet.
  absl::Status AddRobot(const std::string& robot_id, const std::string& kind_name,
                        const Pose2& pose);
  std::vector<std::string> robot_ids() const;
  absl::StatusOr<RobotModel> ModelOf(const std::string& robot_id) const;

  /// The sensor frame of a robot for the current tick.
  absl::StatusOr<SensorFrame> Sense(const std::string& robot_id);
  /// The drive command a robot follows from now on (until the next command).
  absl::Status Command(const std::string& robot_id, const ActuatorCommand& command);
  /// Advances one control tick.
  void Advance();

  uint64_t tick() const { return tick_; }
  int64_t now_ns() const;
  const SimulationParams& params() const { return params_; }
  const WorldDescription& world() const { return description_; }
  GroundTruthSnapshot GroundTruth() const;

 private:
  struct SimRobot {
    std::string robot_id;
    std::unique_ptr<DiffDriveRobot> body;
    std::unique_ptr<ProprioceptiveSensors> sensors;
  };
  Simulation(const WorldDescription& world, SimulationParams params);
  void UpdateSeparation();

  WorldDescription description_;
  SimulationParams params_;
  std::unique_ptr<OdeWorld> world_;
  std::vector<SimRobot> robots_;
  std::map<std::string, size_t> index_;
  std::vector<SimContact> contacts_;
  uint64_t tick_ = 0;
  int steps_per_tick_ = 1;
  double min_separation_m_;
};

}  // namespace fleetnav::sim
