#pragma once

#include <ode/ode.h>

#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "absl/status/status.h"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/core/robot_state.hpp"
#include "fleetnav/core/sensor_frame.hpp"

namespace fleetnav::sim {

using DriveCommand = std::variant<Twist2, WheelSpeeds, AckermannDrive>;

/// A wheel encoder's name (as it appears in SensorFrame.encoders) and its wheel's integrated
/// angle in radians (forward rolling positive).
struct WheelAngle {
  std::string name;
  double angle_rad = 0.0;
};

/// The simulator's view of one robot's body, whatever drives it: physical in ODE (the Lely) or
/// kinematic (omni, Ackermann). The simulation calls, per tick: SetDrive (with the slow-down
/// factor in force), then the physics steps with AfterStep after each, and reads ground truth
/// between ticks. Not thread-safe.
class RobotBody {
 public:
  virtual ~RobotBody() = default;
  virtual const RobotModel& model() const = 0;
  /// InvalidArgument for a kind of command this drive does not take. `scale` multiplies the
  /// command's speeds (the slow-down fault; 1 normally).
  virtual absl::Status SetDrive(const DriveCommand& drive, double scale) = 0;
  /// Called after every physics step. `traction` is ground travel / wheel travel (1 without
  /// slip).
  virtual void AfterStep(double step_s, double traction) = 0;
  virtual Pose2 GroundTruthPose() const = 0;
  virtual Twist2 GroundTruthVelocity() const = 0;  ///< in base_link
  virtual double UpVectorZ() const { return 1.0; }
  /// The steering angle of the virtual front wheel (Ackermann bodies), else nullopt.
  virtual std::optional<double> SteeringAngleRad() const { return std::nullopt; }
  virtual double yaw_rate_radps() const = 0;
  virtual std::vector<WheelAngle> WheelAngles() const = 0;
  /// Whether the body is moved by ODE (else the simulation moves it kinematically).
  virtual bool physical() const = 0;
  /// The ODE body a load is latched to (the chassis).
  virtual dBodyID chassis_body() const = 0;
};

}  // namespace fleetnav::sim
