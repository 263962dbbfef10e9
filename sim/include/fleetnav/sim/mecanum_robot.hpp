#pragma once

#include <ode/ode.h>

#include <array>
#include <cstdint>

#include "absl/status/status.h"
#include "fleetnav/core/pose2.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/core/robot_state.hpp"
#include "fleetnav/sim/mecanum_kinematics.hpp"
#include "fleetnav/sim/noise.hpp"
#include "fleetnav/sim/ode_world.hpp"
#include "fleetnav/sim/robot_body.hpp"

namespace fleetnav::sim {

/// Body geometry of the physical mecanum platform that the RobotModel does not hold (our
/// choices for the KUKA store platform of the thesis's §3: its mecanum wheels are suspended
/// and the passive casters at the corners carry most of the load).
struct MecanumBodyParams {
  double max_wheel_torque_nm = 6.0;
  /// Friction of a mecanum wheel along its roller axis (grip) and across it (the roller's
  /// bearing).
  double roller_grip_mu = 0.8;
  double roller_free_mu = 0.01;
  /// The rubber rollers' creep along the grip (slip speed per newton): forces on the wheels,
  /// as from casters swinging round, move the platform a little without turning them.
  double roller_creep_mps_per_n = 2e-4;
  /// The wheel suspension: a spring pressing each mecanum wheel down with about
  /// spring × preload.
  double suspension_spring_npm = 20000.0;
  double suspension_damper_nspm = 600.0;
  double suspension_preload_m = 0.003;
  /// Four swivel casters, one near each corner, at ±caster_x_m, ±caster_y_m.
  double caster_x_m = 0.34;
  double caster_y_m = 0.10;
  double caster_radius_m = 0.03;
  double caster_trail_m = 0.035;    ///< contact point behind the swivel axis
  double caster_rolling_mu = 0.03;  ///< rolling resistance
  double swivel_friction_nm = 0.4;  ///< friction torque of the loaded swivel bearing
  /// Random swivel angle per square root of second (floor and bearing irregularities): which
  /// way a caster goes round when the motion reverses is not predictable (thesis ch. 9).
  double swivel_noise_rad_per_sqrt_s = 0.01;
  double ground_clearance_m = 0.02;
  double mass_box_height_m = 0.08;

  absl::Status Validate() const;
};

/// The KUKA store platform in ODE (thesis ch. 3–4, 9): a box chassis on four mecanum wheels
/// driven by velocity motors with a torque limit and four passive swivel casters.
///
/// A mecanum wheel is a sprung floor contact of the chassis (a suspension preloaded against the
/// floor) that grips only along its roller axis (45° to the axle: DirectionalFriction) and
/// whose surface moves there at the rim speed, so the wheel rates of MecanumInverse move the
/// platform in any direction; the grip is capped by the motor's torque over the wheel's load,
/// and the rubber creeps under force. A caster is a frictionless load-bearing contact that
/// trails its swivel axis and swivels by the no-side-slip caster law (Siegwart & Nourbakhsh
/// §3.2.1.3: swivel rate = the contact's sideways speed / trail); turning it takes its
/// bearing's friction torque, which pushes the platform sideways at the contact, and rolling
/// resistance pulls back along it. When the motion reverses, the casters swing round —
/// clockwise or counter-clockwise as noise decides — and push the platform off its line, the
/// disturbance the thesis's end-point augmentation avoids. (Wheel and caster bodies on hinges
/// would add 48 constraint rows per platform and cut the simulator's speed by three.) Twists
/// are ramped to the model's acceleration limits as a motor controller would. base_link is the
/// chassis centre on the floor. Not thread-safe; owned by the simulation thread.
class MecanumRobot final : public RobotBody {
 public:
  MecanumRobot(OdeWorld* world, int robot_index, const RobotModel& model, const Pose2& start,
               uint64_t noise_seed, MecanumBodyParams params = {});

  const RobotModel& model() const override { return model_; }
  /// Takes a body twist (clamped to the model's limits).
  absl::Status SetDrive(const DriveCommand& drive, double scale) override;
  void AfterStep(double step_s, double traction) override;
  Pose2 GroundTruthPose() const override;
  Twist2 GroundTruthVelocity() const override;  ///< in base_link
  double UpVectorZ() const override;
  double yaw_rate_radps() const override;
  std::vector<WheelAngle> WheelAngles() const override;
  bool physical() const override { return true; }
  dBodyID chassis_body() const override { return chassis_; }
  /// Heading of caster `i` (FL, FR, RL, RR) relative to the chassis, in (-pi, pi]: the
  /// direction from its contact point to its swivel axis (0 when it trails forward motion).
  double caster_angle_rad(int i) const;
  /// How far caster `i` has swivelled since the start, counter-clockwise positive.
  double caster_swivel_turned_rad(int i) const {
    return swivel_turned_rad_[static_cast<size_t>(i)];
  }

 private:
  void SetWheelRates(const MecanumWheelRates& rates);
  GeomTag* CreateWheel(const Eigen::Vector2d& at, double axle_z_in_chassis_m, double roller_x,
                       double roller_y);
  /// One caster's swivel over a physics step, its forces on the chassis and its contact's
  /// new place.
  void StepCaster(size_t i, double step_s);

  RobotModel model_;
  MecanumBodyParams params_;
  OdeWorld* world_;
  int robot_index_;
  NoiseStream swivel_noise_;
  dBodyID chassis_ = nullptr;
  std::array<GeomTag*, 4> wheel_tags_{};
  std::array<double, 4> wheel_rates_radps_{};
  std::array<Eigen::Vector2d, 4> swivel_axes_m_{};  ///< in base_link
  std::array<dGeomID, 4> caster_geoms_{};
  double caster_z_in_chassis_m_ = 0.0;
  double caster_load_n_ = 0.0;  ///< each caster's share of the weight
  std::array<double, 4> wheel_angles_rad_{};
  std::array<double, 4> swivel_turned_rad_{};
  Twist2 target_;  ///< commanded twist, clamped
  Twist2 ramped_;  ///< what the motors are given, ramped towards target_
};

}  // namespace fleetnav::sim
