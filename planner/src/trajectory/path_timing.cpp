#include "fleetnav/planner/trajectory/path_timing.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/angles.hpp"

namespace fleetnav::planner {
namespace {

constexpr double kEps = 1e-9;

double WrapAngle(double a) { return std::remainder(a, 2.0 * kPi); }

// One sample of a run between stops, before timing.
struct Sample {
  Eigen::Vector2d position_m;
  double yaw_rad;
  double curvature_per_m;  // |curvature| of the step that ends here
  double step_m;           // length along the path of the step that ends here
};

// Appends the samples of the motion from `a` to `b` (straight or arc, direction `sign`)
// without the first one, which the run already holds.
void SampleTranslation(const Pose2& a, const Pose2& b, int sign, double spacing_m,
                       std::vector<Sample>* run) {
  const Eigen::Vector2d p0 = a.translation();
  const double dyaw = WrapAngle(b.yaw_rad() - a.yaw_rad());
  const double chord = (b.translation() - p0).norm();
  const bool arc = std::abs(dyaw) > kEps;
  const double length =
      arc ? chord * (std::abs(dyaw) / 2.0) / std::sin(std::abs(dyaw) / 2.0) : chord;
  const double curvature = arc ? std::abs(dyaw) / length : 0.0;
  const int steps = std::max(1, static_cast<int>(std::ceil(length / spacing_m)));
  for (int k = 1; k <= steps; ++k) {
    const double f = static_cast<double>(k) / steps;
    const double yaw = a.yaw_rad() + dyaw * f;
    Eigen::Vector2d p;
    if (arc) {
      // dp/ds = sign · (cos yaw, sin yaw) with yaw linear in s.
      const double r = sign * length / dyaw;
      p = p0 + r * Eigen::Vector2d(std::sin(yaw) - std::sin(a.yaw_rad()),
                                   -(std::cos(yaw) - std::cos(a.yaw_rad())));
    } else {
      p = p0 + f * (b.translation() - p0);
    }
    run->push_back({p, yaw, curvature, length / steps});
  }
}

// Times one run (at rest at both ends) and appends it to the trajectory.
void TimeRun(const std::vector<Sample>& run, int sign, const MotionLimits& limits,
             Trajectory* out) {
  const size_t n = run.size();
  const double v_max = sign > 0 ? limits.max_speed_mps : limits.max_reverse_speed_mps;
  std::vector<double> v(n), ds(n, 0.0);
  for (size_t i = 0; i < n; ++i) {
    const double kappa =
        std::max(run[i].curvature_per_m, i + 1 < n ? run[i + 1].curvature_per_m : 0.0);
    v[i] = kappa > kEps ? std::min(v_max, limits.max_yaw_rate_radps / kappa) : v_max;
    ds[i] = run[i].step_m;
  }
  v.front() = 0.0;
  v.back() = 0.0;
  for (size_t i = 1; i < n; ++i) {
    v[i] = std::min(v[i], std::sqrt(v[i - 1] * v[i - 1] + 2.0 * limits.max_accel_mps2 * ds[i]));
  }
  for (size_t i = n - 1; i-- > 0;) {
    v[i] = std::min(v[i], std::sqrt(v[i + 1] * v[i + 1] + 2.0 * limits.max_accel_mps2 * ds[i + 1]));
  }
  double t = out->points.empty() ? 0.0 : out->points.back().t_s;
  for (size_t i = 0; i < n; ++i) {
    if (i > 0) {
      const double mean = 0.5 * (v[i] + v[i - 1]);
      t += mean > kEps ? ds[i] / mean : 2.0 * std::sqrt(ds[i] / limits.max_accel_mps2);
    } else if (!out->points.empty()) {
      continue;  // the run starts where the trajectory stands
    }
    const double heading = sign > 0 ? run[i].yaw_rad : WrapAngle(run[i].yaw_rad + kPi);
    out->points.push_back({t, run[i].position_m, run[i].yaw_rad, heading, v[i]});
  }
}

// Appends a turn in place from the trajectory's last yaw by `dyaw`: trapezoidal yaw rate.
void TimeTurn(double dyaw, const MotionLimits& limits, double sample_rad, Trajectory* out) {
  const TrajectoryPoint start = out->points.back();
  const double w = limits.max_yaw_rate_radps, alpha = limits.max_yaw_accel_radps2;
  const double total = std::abs(dyaw);
  const bool reaches_max = total >= w * w / alpha;
  const double t_ramp = reaches_max ? w / alpha : std::sqrt(total / alpha);
  const double t_total = reaches_max ? total / w + w / alpha : 2.0 * t_ramp;
  const double peak = alpha * t_ramp;
  // Angle turned after time s of the profile.
  auto angle_at = [&](double s) {
    if (s <= t_ramp) return 0.5 * alpha * s * s;
    const double ramp_angle = 0.5 * alpha * t_ramp * t_ramp;
    if (s <= t_total - t_ramp) return ramp_angle + peak * (s - t_ramp);
    const double r = t_total - s;
    return total - 0.5 * alpha * r * r;
  };
  const int steps = std::max(1, static_cast<int>(std::ceil(total / sample_rad)));
  for (int k = 1; k <= steps; ++k) {
    const double s = t_total * k / steps;
    const double yaw = start.yaw_rad + std::copysign(angle_at(s), dyaw);
    out->points.push_back({start.t_s + s, start.position_m, yaw, yaw, 0.0});
  }
}

}  // namespace

absl::Status PathTimingParams::Validate() const {
  if (!(sample_spacing_m > 0.0) || !(turn_sample_rad > 0.0)) {
    return absl::InvalidArgumentError("sample_spacing_m and turn_sample_rad: must be > 0");
  }
  return absl::OkStatus();
}

absl::StatusOr<Trajectory> TimePath(const PathResult& path, const RobotModel& model,
                                    const PathTimingParams& params) {
  if (absl::Status s = params.Validate(); !s.ok()) return s;
  if (model.kinematics == Kinematics::kOmnidirectional) {
    return absl::InvalidArgumentError("model: omnidirectional paths are timed by SmoothPath");
  }
  if (path.poses.size() < 2) return absl::InvalidArgumentError("path: fewer than 2 poses");
  const MotionLimits& limits = model.limits;
  if (!(limits.max_speed_mps > 0.0 && limits.max_accel_mps2 > 0.0 &&
        limits.max_yaw_rate_radps > 0.0 && limits.max_yaw_accel_radps2 > 0.0)) {
    return absl::InvalidArgumentError(
        "model.limits: speed, acceleration and yaw limits must be > 0");
  }
  Trajectory out;
  out.intervals = out.raw_intervals = static_cast<int>(path.poses.size()) - 1;
  const Pose2& first = path.poses.front();
  out.points.push_back({0.0, first.translation(), first.yaw_rad(), first.yaw_rad(), 0.0});
  std::vector<Sample> run;
  int run_sign = 0;
  auto flush = [&] {
    if (run.size() > 1) TimeRun(run, run_sign, limits, &out);
    run.clear();
    run_sign = 0;
  };
  for (size_t k = 0; k + 1 < path.poses.size(); ++k) {
    const Pose2& a = path.poses[k];
    const Pose2& b = path.poses[k + 1];
    const Eigen::Vector2d d = b.translation() - a.translation();
    const double dyaw = WrapAngle(b.yaw_rad() - a.yaw_rad());
    if (d.norm() < 1e-6) {
      flush();
      if (std::abs(dyaw) > kEps) TimeTurn(dyaw, limits, params.turn_sample_rad, &out);
      continue;
    }
    const double mid_yaw = a.yaw_rad() + dyaw / 2.0;
    const int sign = d.dot(Eigen::Vector2d(std::cos(mid_yaw), std::sin(mid_yaw))) >= 0.0 ? 1 : -1;
    if (sign < 0 && !(limits.max_reverse_speed_mps > 0.0)) {
      return absl::InvalidArgumentError(absl::StrCat(
          "path.poses[", k, "] -> [", k + 1, "]: backwards, but the model must not reverse"));
    }
    if (sign != run_sign) {
      flush();
      run_sign = sign;
      run.push_back({a.translation(), a.yaw_rad(), 0.0, 0.0});
    }
    SampleTranslation(a, b, sign, params.sample_spacing_m, &run);
  }
  flush();
  return out;
}

absl::StatusOr<Trajectory> TrajectoryForPath(const PathResult& path, Costmap* costmap,
                                             const RobotModel& model) {
  if (model.kinematics == Kinematics::kOmnidirectional) {
    return SmoothPath(path, costmap, model, SmoothingParams{});
  }
  return TimePath(path, model);
}

}  // namespace fleetnav::planner
