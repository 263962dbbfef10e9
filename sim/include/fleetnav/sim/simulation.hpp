#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "fleetnav/core/sensor_frame.hpp"
#include "fleetnav/core/sim_truth.hpp"
#include "fleetnav/sim/ackermann_robot.hpp"
#include "fleetnav/sim/diff_drive_robot.hpp"
#include "fleetnav/sim/exteroceptive_sensors.hpp"
#include "fleetnav/sim/kinematic_robot.hpp"
#include "fleetnav/sim/mecanum_robot.hpp"
#include "fleetnav/sim/ode_world.hpp"
#include "fleetnav/sim/proprioceptive_sensors.hpp"
#include "fleetnav/sim/robot_body.hpp"
#include "fleetnav/sim/trolley_body.hpp"
#include "fleetnav/sim/world_description.hpp"

namespace fleetnav::sim {

/// The robots' battery: drains with time and distance, charges while the charger contact is
/// closed. Rates are fractions of a full charge.
struct BatteryParams {
  double initial_fraction = 1.0;
  double drain_per_s = 1.0 / (12.0 * 3600.0);  ///< electronics: 12 h standing
  double drain_per_m = 1.0 / 6000.0;           ///< driving: 6 km on a charge
  double charge_per_s = 1.0 / 3600.0;          ///< one hour from empty to full
  absl::Status Validate() const;
};

struct SimulationParams {
  double physics_step_s = 0.002;   ///< ≤ 5 ms keeps the heavy robot's yaw tracking ≥ 95 %
  double control_period_s = 0.02;  ///< one lockstep tick (50 Hz)
  uint64_t seed = 1;
  ProprioceptiveParams sensors;
  ExteroceptiveParams exteroceptive;
  /// Omnidirectional robots as kinematic bodies (no wheel slip, casters or contact forces;
  /// cheaper, for large fleets) instead of the physical MecanumRobot.
  bool kinematic_omni = false;
  MecanumBodyParams mecanum;
  /// Ackermann robots as kinematic bodies (the bicycle model, no tyres or contact forces)
  /// instead of the physical AckermannRobot.
  bool kinematic_ackermann = false;
  AckermannBodyParams ackermann;
  BatteryParams battery;
  /// Checks positive steps and that the control period is a whole number of physics steps.
  absl::Status Validate() const;
};

using ::fleetnav::GroundTruthSnapshot;
using ::fleetnav::RobotTruth;
using ::fleetnav::SimContact;
using ::fleetnav::TrolleyTruth;

/// Wall-clock cost of the simulation so far (for the benchmark; never used in behaviour).
struct SimulationTiming {
  double physics_s = 0.0;  ///< Advance: kinematic moves, ODE steps, contacts
  double sensors_s = 0.0;  ///< Sense: every sensor of every robot
  uint64_t ticks = 0;
};

/// One simulated site: the ODE world of a WorldDescription and its robots, advanced in fixed
/// control ticks of whole physics steps. The tick counter is the only clock of a simulated run
/// (sim time = tick × control period). The robots are physical in ODE (omni and Ackermann
/// robots kinematic with SimulationParams::kinematic_omni / kinematic_ackermann: those stop
/// rather than drive into something), and so are the trolleys, which move when pushed and are
/// carried by the lift of a robot that raises it under one (ActuatorCommand::lift_raised: the
/// robot's centre within kLatchRadiusM of the trolley's, aligned within kLatchYawRad). Faults of
/// the world file are in force from the start; InjectFault adds more at run time; Reset starts
/// over. Deterministic for a seed. Not thread-safe: the lockstep coordinator serialises access.
class Simulation {
 public:
  static constexpr double kLatchRadiusM = 0.05;
  static constexpr double kLatchYawRad = 0.1;

  static absl::StatusOr<std::unique_ptr<Simulation>> Create(const WorldDescription& world,
                                                            SimulationParams params);

  /// Adds a robot of a preset kind; AlreadyExists for a duplicate id, NotFound for an unknown
  /// kind, InvalidArgument for an empty id or a non-finite pose.
  absl::Status AddRobot(const std::string& robot_id, const std::string& kind_name,
                        const Pose2& pose);
  std::vector<std::string> robot_ids() const;
  /// The body of robot `robot_id` (for tests and tools that inspect the physics), or nullptr.
  const RobotBody* BodyOf(const std::string& robot_id) const;
  absl::StatusOr<RobotModel> ModelOf(const std::string& robot_id) const;

  /// The sensor frame of a robot for the current tick.
  absl::StatusOr<SensorFrame> Sense(const std::string& robot_id);
  /// The drive command and lift setpoint a robot follows from now on (until the next command);
  /// InvalidArgument for a command its drive does not take or a raised lift it does not have
  /// (the robot keeps its last command).
  absl::Status Command(const std::string& robot_id, const ActuatorCommand& command);
  /// Stops a robot's drive (its agent left); the lift holds where it is, and its load with it.
  void StopDrive(const std::string& robot_id);
  /// Advances one control tick.
  void Advance();

  /// Puts a fault in force from now (for duration_s, 0: until Reset). InvalidArgument for an
  /// empty region or a factor out of range, NotFound for an unknown robot or sensor.
  absl::Status InjectFault(const FaultSpec& fault);
  /// Starts over with a new seed: tick 0, every robot (also spawned ones) back at its start
  /// pose, run-time faults cleared, the world file's faults in force.
  void Reset(uint64_t seed);

  uint64_t tick() const { return tick_; }
  int64_t now_ns() const;
  /// The sim time of `tick` (tick × control period, rounded to whole nanoseconds).
  int64_t TimeOfTickNs(uint64_t tick) const;
  const SimulationParams& params() const { return params_; }
  /// The world as given (without faults).
  const WorldDescription& world() const { return original_; }
  /// The world as it is now (fence and stripe segments removed by faults).
  const WorldDescription& current_world() const { return description_; }
  /// Faults in force now.
  std::vector<FaultSpec> active_faults() const;
  GroundTruthSnapshot GroundTruth() const;
  const SimulationTiming& timing() const { return timing_; }

 private:
  struct SimRobot {
    std::string robot_id;
    std::string kind_name;
    Pose2 start;
    std::unique_ptr<RobotBody> body;
    KinematicRobot* kinematic = nullptr;  ///< body, when it is kinematic
    std::unique_ptr<ProprioceptiveSensors> sensors;
    std::unique_ptr<ExteroceptiveSensors> exteroceptive;
    DriveCommand drive = Twist2{};
    Eigen::Vector2d world_velocity = Eigen::Vector2d::Zero();
    Eigen::Vector2d accel_body = Eigen::Vector2d::Zero();
    double battery_fraction = 1.0;
    bool charger_contact = false;  ///< as last sensed
    bool lift_raised = false;      ///< the lift's setpoint (robots with a lift)
    int carried_trolley = -1;      ///< index into trolleys_, or -1
  };
  struct ActiveFault {
    FaultSpec spec;
    int64_t end_ns = 0;  ///< 0: until Reset
  };
  Simulation(const WorldDescription& world, SimulationParams params);
  void Build();
  absl::Status CreateRobot(const std::string& robot_id, const std::string& kind_name,
                           const Pose2& pose);
  void ApplyWorldFaults();
  void EnsureScene();
  void MoveKinematic(SimRobot& robot, int index, double traction);
  /// Latches the trolley a raised lift stands under, sets down the one a lowered lift carries.
  void UpdateLift(SimRobot& robot, int index);
  double TractionAt(const Pose2& pose) const;
  double SlowFactor(const std::string& robot_id) const;
  std::set<std::string> DroppedSensors(const std::string& robot_id) const;
  void RecordContact(const std::string& robot_id, const std::string& other);
  /// Counts the (robot, other) pairs touching this tick that did not touch the tick before.
  void CountContactEpisodes();
  void UpdateSeparation();

  WorldDescription original_;
  WorldDescription description_;
  SimulationParams params_;
  std::unique_ptr<OdeWorld> world_;
  /// The world's trolleys as bodies in world_ (cleared before it is).
  std::vector<std::unique_ptr<TrolleyBody>> trolleys_;
  std::vector<SimRobot> robots_;  ///< destroyed before world_
  std::map<std::string, size_t> index_;
  std::vector<ActiveFault> faults_;
  std::vector<SimContact> contacts_;
  std::set<std::pair<std::string, std::string>> touching_now_;   ///< (robot, other) this tick
  std::set<std::pair<std::string, std::string>> touching_last_;  ///< … the tick before
  std::map<std::string, std::pair<int, int>> episodes_;  ///< robot → (world, robots) episodes
  SensingScene scene_;
  bool scene_static_valid_ = false;
  uint64_t scene_robots_tick_ = ~uint64_t{0};
  uint64_t tick_ = 0;
  int steps_per_tick_ = 1;
  double min_separation_m_;
  std::set<std::pair<size_t, size_t>> overlapping_;  ///< robot pairs whose footprints overlap
  SimulationTiming timing_;
};

}  // namespace fleetnav::sim
