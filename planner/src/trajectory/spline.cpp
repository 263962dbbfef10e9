#include "fleetnav/planner/trajectory/spline.hpp"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/angles.hpp"

namespace fleetnav::planner {

absl::StatusOr<CubicSpline> CubicSpline::Create(const std::vector<Eigen::Vector2d>& knots,
                                                const Eigen::Vector2d& start_direction,
                                                const Eigen::Vector2d& end_direction) {
  const int n = static_cast<int>(knots.size());
  if (n < 2) return absl::InvalidArgumentError("knots: need at least 2");
  if (!(start_direction.norm() > 0) || !(end_direction.norm() > 0)) {
    return absl::InvalidArgumentError("direction: must be non-zero");
  }
  CubicSpline s;
  s.p_ = knots;
  // Chord-length parameters (eqs. 10.2–10.4).
  std::vector<double> d(n, 0.0);
  for (int i = 1; i < n; ++i) {
    d[i] = (knots[i] - knots[i - 1]).norm();
    if (!(d[i] > 1e-12)) {
      return absl::InvalidArgumentError(absl::StrCat("knots[", i, "]: repeats knots[", i - 1, "]"));
    }
    s.length_m_ += d[i];
  }
  s.u_.assign(n, 0.0);
  for (int i = 1; i < n; ++i) s.u_[i] = s.u_[i - 1] + d[i] / s.length_m_;
  s.u_[n - 1] = 1.0;
  // Gradients: ends given (eq. 10.14, scaled to dX/du ≈ length), interior from C² continuity:
  // Δu_i P'_{i-1} + 2(Δu_{i-1} + Δu_i) P'_i + Δu_{i-1} P'_{i+1}
  //   = 3 (Δu_i / Δu_{i-1} (P_i − P_{i-1}) + Δu_{i-1} / Δu_i (P_{i+1} − P_i)).
  s.dp_.assign(n, Eigen::Vector2d::Zero());
  s.dp_[0] = start_direction.normalized() * s.length_m_;
  s.dp_[n - 1] = end_direction.normalized() * s.length_m_;
  const int m = n - 2;
  if (m > 0) {
    std::vector<double> a(m), b(m), c(m);
    std::vector<Eigen::Vector2d> r(m);
    for (int k = 0; k < m; ++k) {
      const int i = k + 1;
      const double h0 = s.u_[i] - s.u_[i - 1];
      const double h1 = s.u_[i + 1] - s.u_[i];
      a[k] = h1;
      b[k] = 2.0 * (h0 + h1);
      c[k] = h0;
      r[k] = 3.0 * (h1 / h0 * (knots[i] - knots[i - 1]) + h0 / h1 * (knots[i + 1] - knots[i]));
    }
    r[0] -= a[0] * s.dp_[0];
    r[m - 1] -= c[m - 1] * s.dp_[n - 1];
    // Thomas algorithm.
    for (int k = 1; k < m; ++k) {
      const double w = a[k] / b[k - 1];
      b[k] -= w * c[k - 1];
      r[k] -= w * r[k - 1];
    }
    s.dp_[m] = r[m - 1] / b[m - 1];
    for (int k = m - 2; k >= 0; --k) s.dp_[k + 1] = (r[k] - c[k] * s.dp_[k + 2]) / b[k];
  }
  return s;
}

int CubicSpline::Segment(double u) const {
  const int n = static_cast<int>(u_.size());
  const auto it = std::upper_bound(u_.begin(), u_.end(), u);
  return std::clamp(static_cast<int>(it - u_.begin()) - 1, 0, n - 2);
}

Eigen::Vector2d CubicSpline::Evaluate(double u) const {
  const int i = Segment(u);
  const double h = u_[i + 1] - u_[i];
  const double s = (u - u_[i]) / h;
  const double s2 = s * s, s3 = s2 * s;
  // Eq. 10.12 in the normalised local parameter s.
  return (2 * s3 - 3 * s2 + 1) * p_[i] + (-2 * s3 + 3 * s2) * p_[i + 1] +
         h * (s3 - 2 * s2 + s) * dp_[i] + h * (s3 - s2) * dp_[i + 1];
}

Eigen::Vector2d CubicSpline::Derivative(double u) const {
  const int i = Segment(u);
  const double h = u_[i + 1] - u_[i];
  const double s = (u - u_[i]) / h;
  const double s2 = s * s;
  return ((6 * s2 - 6 * s) * p_[i] + (-6 * s2 + 6 * s) * p_[i + 1]) / h +
         (3 * s2 - 4 * s + 1) * dp_[i] + (3 * s2 - 2 * s) * dp_[i + 1];
}

Eigen::Vector2d CubicSpline::SecondDerivative(double u) const {
  const int i = Segment(u);
  const double h = u_[i + 1] - u_[i];
  const double s = (u - u_[i]) / h;
  return ((12 * s - 6) * p_[i] + (-12 * s + 6) * p_[i + 1]) / (h * h) +
         ((6 * s - 4) * dp_[i] + (6 * s - 2) * dp_[i + 1]) / h;
}

std::vector<Eigen::Vector2d> CubicSpline::Sample(double points_per_metre) const {
  const int count = std::max(static_cast<int>(p_.size()),
                             static_cast<int>(std::ceil(length_m_ * points_per_metre)) + 1);
  std::vector<Eigen::Vector2d> out;
  out.reserve(count);
  for (int k = 0; k < count; ++k) out.push_back(Evaluate(static_cast<double>(k) / (count - 1)));
  return out;
}

std::vector<Eigen::Vector2d> AugmentEndpoints(const std::vector<Eigen::Vector2d>& knots,
                                              double radius_m, double max_turn_rad) {
  std::vector<Eigen::Vector2d> out;
  for (size_t i = 0; i < knots.size(); ++i) {
    out.push_back(knots[i]);
    if (i == 0 || i + 1 >= knots.size()) continue;
    const Eigen::Vector2d a = (knots[i] - knots[i - 1]).normalized();
    const Eigen::Vector2d b = (knots[i + 1] - knots[i]).normalized();
    const double turn = std::acos(std::clamp(a.dot(b), -1.0, 1.0));
    if (turn <= max_turn_rad) continue;
    const Eigen::Vector2d left(-a.y(), a.x());
    Eigen::Vector2d outward = a - b;
    outward = outward.norm() > 1e-9 ? outward.normalized() : a;
    out.push_back(knots[i] + radius_m * (outward + left).normalized());
  }
  return out;
}

absl::StatusOr<std::vector<TimedPose>> TimeParameterize(const std::vector<Eigen::Vector2d>& path,
                                                        const MotionLimits& limits) {
  const int n = static_cast<int>(path.size());
  if (n < 2) return absl::InvalidArgumentError("path: need at least 2 points");
  if (!(limits.max_speed_mps > 0) || !(limits.max_yaw_rate_radps > 0) ||
      !(limits.max_accel_mps2 > 0)) {
    return absl::InvalidArgumentError("limits: speed, yaw rate and acceleration must be > 0");
  }
  std::vector<double> ds(n, 0.0), yaw(n, 0.0), vmax(n, limits.max_speed_mps);
  for (int i = 1; i < n; ++i) ds[i] = (path[i] - path[i - 1]).norm();
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d d = path[std::min(i + 1, n - 1)] - path[std::max(i - 1, 0)];
    yaw[i] = std::atan2(d.y(), d.x());
  }
  // Curvature from the turn between neighbouring samples: v ≤ ω_max / κ.
  for (int i = 1; i + 1 < n; ++i) {
    const double turn = std::abs(
        std::remainder(std::atan2(path[i + 1].y() - path[i].y(), path[i + 1].x() - path[i].x()) -
                           std::atan2(path[i].y() - path[i - 1].y(), path[i].x() - path[i - 1].x()),
                       2 * kPi));
    const double arc = 0.5 * (ds[i] + ds[i + 1]);
    if (turn > 1e-12 && arc > 0) {
      vmax[i] = std::min(vmax[i], limits.max_yaw_rate_radps * arc / turn);
    }
  }
  std::vector<double> v = vmax;
  v[0] = 0.0;
  v[n - 1] = 0.0;
  for (int i = 1; i < n; ++i) {
    v[i] = std::min(v[i], std::sqrt(v[i - 1] * v[i - 1] + 2 * limits.max_accel_mps2 * ds[i]));
  }
  for (int i = n - 2; i >= 0; --i) {
    v[i] = std::min(v[i], std::sqrt(v[i + 1] * v[i + 1] + 2 * limits.max_accel_mps2 * ds[i + 1]));
  }
  std::vector<TimedPose> out(n);
  double t = 0.0;
  for (int i = 0; i < n; ++i) {
    if (i > 0) {
      const double mean = 0.5 * (v[i] + v[i - 1]);
      t += mean > 1e-12 ? ds[i] / mean : 0.0;
    }
    out[i] = {t, path[i], yaw[i], v[i]};
  }
  return out;
}

}  // namespace fleetnav::planner
