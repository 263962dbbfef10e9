#include "fleetnav/sim/proprioceptive_sensors.hpp"

#include <cmath>

#include "fleetnav/core/angles.hpp"

namespace fleetnav::sim {

ProprioceptiveSensors::ProprioceptiveSensors(ProprioceptiveParams params, uint64_t simulation_seed,
                                             const std::string& robot_id)
    : params_(params),
      gyro_noise_(NoiseSeed(simulation_seed, robot_id, "gyro")),
      accel_noise_(NoiseSeed(simulation_seed, robot_id, "accelerometer")) {}

int64_t ProprioceptiveSensors::Ticks(double angle_rad) const {
  const double revolutions = angle_rad / (2.0 * kPi);
  return static_cast<int64_t>(std::floor(revolutions * params_.encoder_ticks_per_rev *
                                         (1.0 + params_.wheel_radius_scale_error)));
}

void ProprioceptiveSensors::Sample(double left_wheel_angle_rad, double right_wheel_angle_rad,
                                   double yaw_rate_radps, double period_s, SensorFrame* frame) {
  frame->encoders = {{"left", Ticks(left_wheel_angle_rad)},
                     {"right", Ticks(right_wheel_angle_rad)}};
  gyro_bias_radps_ +=
      gyro_noise_.Gaussian(params_.gyro_bias_walk_radps_per_sqrt_s * std::sqrt(period_s));
  const double white_stddev = params_.gyro_noise_density_radps_per_sqrt_hz / std::sqrt(period_s);
  frame->imu.gyro_z_radps = yaw_rate_radps + gyro_bias_radps_ + gyro_noise_.Gaussian(white_stddev);
}

void ProprioceptiveSensors::SampleEncoders(const std::vector<WheelAngle>& wheels,
                                           SensorFrame* frame) const {
  frame->encoders.clear();
  for (const WheelAngle& wheel : wheels)
    frame->encoders.push_back({wheel.name, Ticks(wheel.angle_rad)});
}

void ProprioceptiveSensors::SampleSteering(std::optional<double> steering_rad,
                                           SensorFrame* frame) const {
  frame->steering_angle_rad.reset();
  if (!steering_rad) return;
  const double step = params_.steering_resolution_rad;
  frame->steering_angle_rad = step > 0.0 ? std::round(*steering_rad / step) * step : *steering_rad;
}

void ProprioceptiveSensors::SampleImu(double yaw_rate_radps, double accel_x_mps2,
                                      double accel_y_mps2, double period_s, SensorFrame* frame) {
  gyro_bias_radps_ +=
      gyro_noise_.Gaussian(params_.gyro_bias_walk_radps_per_sqrt_s * std::sqrt(period_s));
  const double white_stddev = params_.gyro_noise_density_radps_per_sqrt_hz / std::sqrt(period_s);
  frame->imu.gyro_z_radps = yaw_rate_radps + gyro_bias_radps_ + gyro_noise_.Gaussian(white_stddev);
  frame->imu.accel_x_mps2 = accel_x_mps2 + accel_noise_.Gaussian(params_.accel_noise_stddev_mps2);
  frame->imu.accel_y_mps2 = accel_y_mps2 + accel_noise_.Gaussian(params_.accel_noise_stddev_mps2);
}

}  // namespace fleetnav::sim
