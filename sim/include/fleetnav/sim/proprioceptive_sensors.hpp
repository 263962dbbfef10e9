#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/sensor_frame.hpp"
#include "fleetnav/sim/noise.hpp"
#include "fleetnav/sim/robot_body.hpp"

namespace fleetnav::sim {

/// Parameters of the wheel encoders and the gyro of one robot.
struct ProprioceptiveParams {
  int encoder_ticks_per_rev = 4096;
  /// Relative error of the wheel radius the encoders imply (0.01 = 1 % too large).
  double wheel_radius_scale_error = 0.0;
  /// Gyro white noise (Lely thesis ch. 3: 0.015 °/s/√Hz).
  double gyro_noise_density_radps_per_sqrt_hz = 0.00026179938779914914;  ///< 0.015 °/s/√Hz
  /// Gyro bias random walk (rad/s per √s).
  double gyro_bias_walk_radps_per_sqrt_s = 1e-5;
  /// Accelerometer white noise per sample (m/s²).
  double accel_noise_stddev_mps2 = 0.02;
  /// Resolution of an Ackermann robot's steering-angle encoder (12 bits a turn).
  double steering_resolution_rad = 0.0015339807878856397;  ///< 12 bits a turn
};

/// Wheel encoders (cumulative ticks from the integrated wheel angle, thesis eq. 3.4's input)
/// and a z-gyro with white noise and a random-walk bias, each on its own seeded noise stream.
/// Not thread-safe.
class ProprioceptiveSensors {
 public:
  ProprioceptiveSensors(ProprioceptiveParams params, uint64_t simulation_seed,
                        const std::string& robot_id);

  /// Fills frame->encoders ("left", "right") and frame->imu for one control period.
  void Sample(double left_wheel_angle_rad, double right_wheel_angle_rad, double yaw_rate_radps,
              double period_s, SensorFrame* frame);
  /// Encoders of any drive: one reading per wheel, named as the body names them.
  void SampleEncoders(const std::vector<WheelAngle>& wheels, SensorFrame* frame) const;
  /// The steering encoder's reading of `steering_rad` (nothing for robots that do not steer).
  void SampleSteering(std::optional<double> steering_rad, SensorFrame* frame) const;
  /// Gyro and accelerometer (body-frame acceleration, gravity removed), each with noise.
  void SampleImu(double yaw_rate_radps, double accel_x_mps2, double accel_y_mps2, double period_s,
                 SensorFrame* frame);

 private:
  int64_t Ticks(double angle_rad) const;

  ProprioceptiveParams params_;
  NoiseStream gyro_noise_;
  NoiseStream accel_noise_;
  double gyro_bias_radps_ = 0.0;
};

}  // namespace fleetnav::sim
