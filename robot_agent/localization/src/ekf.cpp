#include <cmath>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/localization/odometry.hpp"

namespace fleetnav::localization {

absl::Status OdomEkfParams::Validate() const {
  const std::pair<double, const char*> all[] = {
      {accel_noise_mps2, "accel_noise_mps2"},
      {yaw_accel_noise_radps2, "yaw_accel_noise_radps2"},
      {wheel_speed_stddev_mps, "wheel_speed_stddev_mps"},
      {wheel_yaw_rate_stddev_radps, "wheel_yaw_rate_stddev_radps"},
      {gyro_stddev_radps, "gyro_stddev_radps"},
      {gyro_bias_walk_radps, "gyro_bias_walk_radps"}};
  for (const auto& [value, name] : all) {
    if (!(std::isfinite(value) && value > 0.0)) {
      return absl::InvalidArgumentError(absl::StrCat(name, " must be finite and > 0"));
    }
  }
  return absl::OkStatus();
}

OdomEkf::OdomEkf(const OdomEkfParams& params) : params_(params) {
  state_.setZero();
  cov_.setZero();
  cov_.diagonal() << 1e-9, 1e-9, 1e-9, 1.0, 1.0, 1.0, 1e-4;
}

absl::Status OdomEkf::Predict(double dt_s) {
  if (!(std::isfinite(dt_s) && dt_s >= 0.0)) {
    return absl::InvalidArgumentError(absl::StrCat("dt_s must be finite and >= 0, got ", dt_s));
  }
  if (dt_s == 0.0) return absl::OkStatus();
  const double yaw = state_(2);
  const double vx = state_(3);
  const double vy = state_(4);
  const double c = std::cos(yaw);
  const double s = std::sin(yaw);
  state_(0) += (c * vx - s * vy) * dt_s;
  state_(1) += (s * vx + c * vy) * dt_s;
  state_(2) = NormalizeAngle(yaw + state_(5) * dt_s);

  Eigen::Matrix<double, 7, 7> f = Eigen::Matrix<double, 7, 7>::Identity();
  f(0, 2) = (-s * vx - c * vy) * dt_s;
  f(0, 3) = c * dt_s;
  f(0, 4) = -s * dt_s;
  f(1, 2) = (c * vx - s * vy) * dt_s;
  f(1, 3) = s * dt_s;
  f(1, 4) = c * dt_s;
  f(2, 5) = dt_s;
  Eigen::Matrix<double, 7, 7> q = Eigen::Matrix<double, 7, 7>::Zero();
  const double a2 = params_.accel_noise_mps2 * params_.accel_noise_mps2;
  const double w2 = params_.yaw_accel_noise_radps2 * params_.yaw_accel_noise_radps2;
  q(3, 3) = a2 * dt_s;
  q(4, 4) = a2 * dt_s;
  q(5, 5) = w2 * dt_s;
  q(6, 6) = params_.gyro_bias_walk_radps * params_.gyro_bias_walk_radps * dt_s;
  cov_ = f * cov_ * f.transpose() + q;
  return absl::OkStatus();
}

void OdomEkf::Fuse(const Eigen::Matrix<double, Eigen::Dynamic, 7>& h,
                   const Eigen::VectorXd& innovation, const Eigen::MatrixXd& noise) {
  const Eigen::MatrixXd s = h * cov_ * h.transpose() + noise;
  const Eigen::MatrixXd k = cov_ * h.transpose() * s.inverse();
  state_ += k * innovation;
  state_(2) = NormalizeAngle(state_(2));
  // Joseph form keeps the covariance symmetric and positive semi-definite.
  const Eigen::Matrix<double, 7, 7> i_kh = Eigen::Matrix<double, 7, 7>::Identity() - k * h;
  cov_ = i_kh * cov_ * i_kh.transpose() + k * noise * k.transpose();
}

void OdomEkf::FuseWheelTwist(const Eigen::Vector3d& twist) {
  Eigen::Matrix<double, Eigen::Dynamic, 7> h = Eigen::Matrix<double, 3, 7>::Zero();
  h(0, 3) = 1.0;
  h(1, 4) = 1.0;
  h(2, 5) = 1.0;
  const Eigen::VectorXd innovation = twist - state_.segment<3>(3);
  Eigen::MatrixXd noise = Eigen::MatrixXd::Zero(3, 3);
  noise(0, 0) = noise(1, 1) = params_.wheel_speed_stddev_mps * params_.wheel_speed_stddev_mps;
  noise(2, 2) = params_.wheel_yaw_rate_stddev_radps * params_.wheel_yaw_rate_stddev_radps;
  Fuse(h, innovation, noise);
}

void OdomEkf::FuseGyro(double yaw_rate_radps) {
  Eigen::Matrix<double, Eigen::Dynamic, 7> h = Eigen::Matrix<double, 1, 7>::Zero();
  h(0, 5) = 1.0;
  h(0, 6) = 1.0;
  Eigen::VectorXd innovation(1);
  innovation(0) = yaw_rate_radps - (state_(5) + state_(6));
  Eigen::MatrixXd noise(1, 1);
  noise(0, 0) = params_.gyro_stddev_radps * params_.gyro_stddev_radps;
  Fuse(h, innovation, noise);
}

Pose2 OdomEkf::pose_in_odom() const { return Pose2(state_(0), state_(1), state_(2)); }

}  // namespace fleetnav::localization
