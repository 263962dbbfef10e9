#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>

namespace fleetnav {

/// A rigid transform in SE(2): translation (x_m, y_m) and rotation yaw_rad, the yaw kept in
/// (-pi, pi]. `a * b` composes (apply b, then a: T_ac = T_ab * T_bc), `Inverse()` inverts, and
/// `Between(a, b)` is the pose of b seen from a (a⁻¹·b). Frames follow REP 105: a pose named
/// `pose_in_map` is the transform map → base_link. A plain value type; thread-compatible.
class Pose2 {
 public:
  Pose2() = default;
  Pose2(double x_m, double y_m, double yaw_rad);

  double x_m() const { return x_m_; }
  double y_m() const { return y_m_; }
  double yaw_rad() const { return yaw_rad_; }
  Eigen::Vector2d translation() const { return {x_m_, y_m_}; }

  Pose2 operator*(const Pose2& other) const;
  Pose2 Inverse() const;
  /// Maps a point given in this pose's frame to the parent frame.
  Eigen::Vector2d TransformPoint(const Eigen::Vector2d& point) const;
  Eigen::Isometry2d ToIsometry() const;
  static Pose2 FromIsometry(const Eigen::Isometry2d& iso);

  /// True when positions differ by at most tolerance_m and yaws by at most tolerance_rad.
  bool IsNear(const Pose2& other, double tolerance_m, double tolerance_rad) const;
  /// True when all three components are finite.
  bool IsFinite() const;
  std::string DebugString() const;

 private:
  double x_m_ = 0.0;
  double y_m_ = 0.0;
  double yaw_rad_ = 0.0;
};

/// Pose of `b` expressed in the frame of `a`: a⁻¹ · b.
Pose2 Between(const Pose2& a, const Pose2& b);

}  // namespace fleetnav
