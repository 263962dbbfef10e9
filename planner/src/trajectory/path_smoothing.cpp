#include "fleetnav/planner/trajectory/path_smoothing.hpp"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/planner/trajectory/spline.hpp"

namespace fleetnav::planner {
namespace {

double AngleDiff(double a, double b) { return std::remainder(a - b, 2.0 * kPi); }

// A distinct position of the path: the yaw on arrival and after any turn in place there.
struct Knot {
  Eigen::Vector2d p;
  double yaw_in;
  double yaw_out;
};

struct Sample {
  Eigen::Vector2d p;
  double yaw;
  int interval;  // -1: the final knot
  bool stop;     // the robot is at rest here
};

std::vector<Knot> Knots(const PathResult& path) {
  std::vector<Knot> knots;
  for (const Pose2& pose : path.poses) {
    const Eigen::Vector2d p = pose.translation();
    if (!knots.empty() && (p - knots.back().p).norm() < 1e-9) {
      knots.back().yaw_out = pose.yaw_rad();
    } else {
      knots.push_back({p, pose.yaw_rad(), pose.yaw_rad()});
    }
  }
  return knots;
}

// Samples of a turn in place at `p` from yaw a to b (both ends excluded), at rest.
void TurnInPlace(const Eigen::Vector2d& p, double a, double b, double step_rad, int interval,
                 std::vector<Sample>* out) {
  const double d = AngleDiff(b, a);
  const int n = static_cast<int>(std::ceil(std::abs(d) / step_rad));
  for (int k = 1; k < n; ++k) out->push_back({p, a + d * k / n, interval, true});
  if (std::abs(d) > 1e-12) out->push_back({p, b, interval, true});
}

class Smoother {
 public:
  Smoother(std::vector<Knot> knots, double spacing_m, double corner_radius_m,
           const SmoothingParams& params)
      : k_(std::move(knots)),
        spacing_m_(spacing_m),
        corner_radius_m_(corner_radius_m),
        params_(params) {}

  int intervals() const { return static_cast<int>(k_.size()) - 1; }

  Eigen::Vector2d Direction(int interval) const {
    return (k_[interval + 1].p - k_[interval].p).normalized();
  }

  // The samples with the intervals in `raw` kept straight and the others splined.
  absl::StatusOr<std::vector<Sample>> Build(const std::vector<bool>& raw) const {
    std::vector<Sample> out;
    const int m = intervals();
    const double yaw_step = spacing_m_ / std::max(corner_radius_m_, 1e-3);
    int j = 0;
    while (j < m) {
      if (raw[j]) {
        const Knot& a = k_[j];
        const bool corner = j > 0 && raw[j - 1] && Direction(j - 1).dot(Direction(j)) < 1.0 - 1e-9;
        const bool turn = std::abs(AngleDiff(a.yaw_out, a.yaw_in)) > 1e-12;
        out.push_back({a.p, a.yaw_in, j, corner || turn});
        TurnInPlace(a.p, a.yaw_in, a.yaw_out, yaw_step, j, &out);
        AppendStraight(j, a.yaw_out, &out);
        ++j;
        continue;
      }
      int end = j;  // the run is intervals j .. end-1
      while (end < m && !raw[end]) ++end;
      if (absl::Status s = AppendSpline(j, end, raw, &out); !s.ok()) return s;
      j = end;
    }
    const Knot& last = k_.back();
    const bool corner = m > 0 && raw[m - 1];  // a straight segment ends at rest anyway
    out.push_back({last.p, last.yaw_in, -1, corner});
    TurnInPlace(last.p, last.yaw_in, last.yaw_out, yaw_step, -1, &out);
    return out;
  }

 private:
  // Straight from knot j to j + 1 (start and end excluded), the yaw from `yaw_from` to the next
  // knot's arrival yaw.
  void AppendStraight(int j, double yaw_from, std::vector<Sample>* out) const {
    const Knot& a = k_[j];
    const Knot& b = k_[j + 1];
    const double dyaw = AngleDiff(b.yaw_in, yaw_from);
    const double sweep = (b.p - a.p).norm() + corner_radius_m_ * std::abs(dyaw);
    const int n = std::max(1, static_cast<int>(std::ceil(sweep / spacing_m_)));
    for (int k = 1; k < n; ++k) {
      const double f = static_cast<double>(k) / n;
      out->push_back({a.p + f * (b.p - a.p), yaw_from + f * dyaw, j, false});
    }
  }

  // One spline through knots first .. last_interval (exclusive end interval index `end`).
  absl::Status AppendSpline(int first, int end, const std::vector<bool>& raw,
                            std::vector<Sample>* out) const {
    std::vector<Eigen::Vector2d> knots;
    for (int i = first; i <= end; ++i) knots.push_back(k_[i].p);
    const std::vector<Eigen::Vector2d> augmented =
        AugmentEndpoints(knots, params_.augment_radius_m, params_.augment_max_turn_rad);
    // Where each original knot landed among the augmented ones.
    std::vector<int> at(knots.size(), 0);
    for (size_t i = 0, a = 0; i < knots.size(); ++a) {
      if (augmented[a] == knots[i]) at[i++] = static_cast<int>(a);
    }
    // End tangents: along the neighbouring straight segment, else along the first/last chord.
    const Eigen::Vector2d start_dir =
        first > 0 && raw[first - 1] ? Direction(first - 1) : Direction(first);
    const Eigen::Vector2d end_dir =
        end < intervals() && raw[end] ? Direction(end) : Direction(end - 1);
    absl::StatusOr<CubicSpline> spline = CubicSpline::Create(augmented, start_dir, end_dir);
    if (!spline.ok()) return spline.status();
    const std::vector<double>& u = spline->parameters();
    for (int j = first; j < end; ++j) {
      const int a0 = at[j - first], a1 = at[j - first + 1];
      double polygon_m = 0.0;
      for (int a = a0; a < a1; ++a) polygon_m += (augmented[a + 1] - augmented[a]).norm();
      const double dyaw = AngleDiff(k_[j + 1].yaw_in, k_[j].yaw_in);
      // A cubic arc is at most ~1.5× its control polygon here; sample generously.
      const double sweep = 1.5 * polygon_m + corner_radius_m_ * std::abs(dyaw);
      const int n = std::max(2, static_cast<int>(std::ceil(sweep / spacing_m_)));
      for (int k = 0; k < n; ++k) {
        const double f = static_cast<double>(k) / n;
        const Eigen::Vector2d p = k == 0 ? k_[j].p : spline->Evaluate(u[a0] + f * (u[a1] - u[a0]));
        out->push_back({p, k_[j].yaw_in + f * dyaw, j, false});
      }
    }
    return absl::OkStatus();
  }

  std::vector<Knot> k_;
  double spacing_m_;
  double corner_radius_m_;
  SmoothingParams params_;
};

// The two-pass speed profile over the samples (see SmoothPath).
Trajectory Time(const std::vector<Sample>& s, const MotionLimits& limits) {
  const int n = static_cast<int>(s.size());
  const double w = limits.max_yaw_rate_radps, acc = limits.max_accel_mps2;
  std::vector<double> ds(n, 0.0), dyaw(n, 0.0), vmax(n, limits.max_speed_mps);
  for (int i = 1; i < n; ++i) {
    ds[i] = (s[i].p - s[i - 1].p).norm();
    dyaw[i] = std::abs(AngleDiff(s[i].yaw, s[i - 1].yaw));
  }
  for (int i = 0; i < n; ++i) {
    if (s[i].stop) vmax[i] = 0.0;
  }
  vmax[0] = 0.0;
  vmax[n - 1] = 0.0;
  for (int i = 1; i < n; ++i) {
    if (dyaw[i] <= 1e-12) continue;
    // Platform yaw rate: v ≤ ω ds / Δψ at both ends of the step (0 for a turn in place).
    const double bound = w * ds[i] / dyaw[i];
    vmax[i - 1] = std::min(vmax[i - 1], bound);
    vmax[i] = std::min(vmax[i], bound);
  }
  std::vector<double> heading(n, 0.0);
  bool have_heading = false;
  for (int i = 0; i + 1 < n; ++i) {
    if (ds[i + 1] > 1e-12) {
      heading[i] = std::atan2(s[i + 1].p.y() - s[i].p.y(), s[i + 1].p.x() - s[i].p.x());
      have_heading = true;
    } else {
      heading[i] = i > 0 ? heading[i - 1] : 0.0;
    }
  }
  if (n > 1) heading[n - 1] = heading[n - 2];
  if (have_heading) {  // backfill the heading of leading turns in place
    int first = 0;
    while (ds[first + 1] <= 1e-12) ++first;
    for (int i = 0; i < first; ++i) heading[i] = heading[first];
  }
  for (int i = 1; i + 1 < n; ++i) {
    if (ds[i] <= 1e-12 || ds[i + 1] <= 1e-12) continue;
    // Direction of travel: v ≤ ω / κ with κ = turn / mean step.
    const double turn = std::abs(AngleDiff(heading[i], heading[i - 1]));
    if (turn > 1e-12) vmax[i] = std::min(vmax[i], w * 0.5 * (ds[i] + ds[i + 1]) / turn);
  }
  std::vector<double> v = vmax;
  for (int i = 1; i < n; ++i)
    v[i] = std::min(v[i], std::sqrt(v[i - 1] * v[i - 1] + 2 * acc * ds[i]));
  for (int i = n - 2; i >= 0; --i) {
    v[i] = std::min(v[i], std::sqrt(v[i + 1] * v[i + 1] + 2 * acc * ds[i + 1]));
  }
  Trajectory out;
  out.points.resize(n);
  double t = 0.0;
  for (int i = 0; i < n; ++i) {
    if (i > 0) {
      double dt = 0.0;
      if (ds[i] > 0.0) {
        const double sum = v[i - 1] + v[i];
        dt = sum > 1e-9 ? 2.0 * ds[i] / sum : 2.0 * std::sqrt(ds[i] / acc);
      }
      t += std::max(dt, dyaw[i] / w);
    }
    out.points[i] = {t, s[i].p, s[i].yaw, heading[i], v[i]};
  }
  return out;
}

}  // namespace

absl::Status SmoothingParams::Validate() const {
  if (!(sample_spacing_m > 0.0) || !std::isfinite(sample_spacing_m)) {
    return absl::InvalidArgumentError("sample_spacing_m: must be finite and > 0");
  }
  if (!(augment_radius_m > 0.0) || !std::isfinite(augment_radius_m)) {
    return absl::InvalidArgumentError("augment_radius_m: must be finite and > 0");
  }
  if (!(augment_max_turn_rad > 0.0 && augment_max_turn_rad <= kPi)) {
    return absl::InvalidArgumentError("augment_max_turn_rad: must be in (0, pi]");
  }
  return absl::OkStatus();
}

absl::StatusOr<Trajectory> SmoothPath(const PathResult& path, Costmap* costmap,
                                      const RobotModel& model, const SmoothingParams& params) {
  if (absl::Status s = params.Validate(); !s.ok()) return s;
  if (costmap == nullptr) return absl::InvalidArgumentError("costmap: null");
  if (model.kinematics != Kinematics::kOmnidirectional) {
    return absl::InvalidArgumentError(
        absl::StrCat("model: smoothing moves sideways; needs an omnidirectional model, not ",
                     std::string(KinematicsName(model.kinematics))));
  }
  const MotionLimits& limits = model.limits;
  if (!(limits.max_speed_mps > 0) || !(limits.max_yaw_rate_radps > 0) ||
      !(limits.max_accel_mps2 > 0)) {
    return absl::InvalidArgumentError(
        "model.limits: max_speed_mps, max_yaw_rate_radps and max_accel_mps2 must be > 0");
  }
  if (path.poses.empty()) return absl::InvalidArgumentError("path: no poses");
  for (const Pose2& p : path.poses) {
    if (!p.IsFinite()) return absl::InvalidArgumentError("path: pose not finite");
  }
  const double spacing_m = std::min(params.sample_spacing_m, 0.5 * costmap->resolution_m());
  Smoother smoother(Knots(path), spacing_m, costmap->circumscribed_radius_m(), params);
  std::vector<bool> raw(std::max(0, smoother.intervals()), false);
  std::vector<Sample> samples;
  for (;;) {
    absl::StatusOr<std::vector<Sample>> built = smoother.Build(raw);
    if (!built.ok()) return built.status();
    samples = *std::move(built);
    bool changed = false;
    for (const Sample& s : samples) {
      if (s.interval < 0 || raw[s.interval]) continue;
      if (!costmap->PoseFree(s.p.x(), s.p.y(), s.yaw)) {
        raw[s.interval] = true;
        changed = true;
      }
    }
    if (!changed) break;
  }
  Trajectory out = Time(samples, limits);
  out.intervals = smoother.intervals();
  out.raw_intervals = static_cast<int>(std::count(raw.begin(), raw.end(), true));
  return out;
}

}  // namespace fleetnav::planner
