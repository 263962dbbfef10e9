#include "fleetnav/localization/sensor_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/distance_transform.hpp"

namespace fleetnav::localization {
namespace {

absl::Status CheckRange(double value, double lo, double hi, const char* field) {
  if (std::isfinite(value) && value >= lo && value <= hi) return absl::OkStatus();
  return absl::InvalidArgumentError(
      absl::StrCat(field, " must be in [", lo, ", ", hi, "], got ", value));
}

// "No obstacle" for the distance transform: a large finite value keeps the parabola
// intersections finite.
constexpr double kFar = 1e12;

}  // namespace

std::vector<double> BeamRayAngles(const RangeBeam& beam) {
  constexpr double kMaxSpacingRad = kPi / 180.0;
  if (!(beam.cone_rad > 0.0)) return {beam.angle_in_base_rad};
  const int gaps = std::max(2, static_cast<int>(std::ceil(beam.cone_rad / kMaxSpacingRad)));
  std::vector<double> angles;
  angles.reserve(gaps + 1);
  for (int k = 0; k <= gaps; ++k) {
    angles.push_back(beam.angle_in_base_rad +
                     beam.cone_rad * (static_cast<double>(k) / gaps - 0.5));
  }
  return angles;
}

RangeObservation ObservationFromLaser(const LaserScanSample& scan, const Pose2& mount_in_base,
                                      int max_beams) {
  RangeObservation observation;
  const int total = static_cast<int>(scan.ranges_m.size());
  if (total == 0) return observation;
  const int count = (max_beams <= 0 || max_beams >= total) ? total : max_beams;
  observation.beams.reserve(count);
  for (int j = 0; j < count; ++j) {
    const int i = static_cast<int>(static_cast<int64_t>(j) * total / count);
    const double r = scan.ranges_m[i];
    RangeBeam beam;
    beam.origin_in_base = mount_in_base.translation();
    beam.angle_in_base_rad =
        mount_in_base.yaw_rad() + scan.angle_min_rad + i * scan.angle_increment_rad;
    beam.range_max_m = scan.range_max_m;
    beam.no_echo = !std::isfinite(r) || r >= scan.range_max_m;
    beam.range_m = beam.no_echo ? scan.range_max_m : r;
    observation.beams.push_back(beam);
  }
  return observation;
}

absl::StatusOr<RangeObservation> FakeLaserFromUltrasonics(const std::vector<RangeReading>& readings,
                                                          const RobotModel& model,
                                                          double range_max_m, double cone_rad) {
  if (!(std::isfinite(range_max_m) && range_max_m > 0.0)) {
    return absl::InvalidArgumentError("range_max_m must be finite and > 0");
  }
  if (!(std::isfinite(cone_rad) && cone_rad >= 0.0 && cone_rad < kPi)) {
    return absl::InvalidArgumentError("cone_rad must be in [0, pi)");
  }
  RangeObservation observation;
  for (const RangeReading& reading : readings) {
    const SensorMount* mount = model.FindSensor(reading.name);
    if (mount == nullptr) {
      return absl::InvalidArgumentError(absl::StrCat("ultrasonic reading '", reading.name,
                                                     "' has no mount on ", model.kind_name));
    }
    RangeBeam beam;
    beam.origin_in_base = mount->pose_in_base.translation();
    beam.angle_in_base_rad = mount->pose_in_base.yaw_rad();
    beam.range_max_m = range_max_m;
    beam.no_echo =
        !reading.echo || !std::isfinite(reading.range_m) || reading.range_m >= range_max_m;
    beam.range_m = beam.no_echo ? range_max_m : reading.range_m;
    beam.cone_rad = cone_rad;
    observation.beams.push_back(beam);
  }
  return observation;
}

absl::Status LikelihoodFieldParams::Validate() const {
  if (absl::Status s = CheckRange(sigma_hit_m, 1e-4, 10.0, "sigma_hit_m"); !s.ok()) return s;
  if (absl::Status s = CheckRange(z_hit, 0.0, 1.0, "z_hit"); !s.ok()) return s;
  if (absl::Status s = CheckRange(z_rand, 1e-9, 1.0, "z_rand"); !s.ok()) return s;
  if (absl::Status s = CheckRange(z_rand_range_m, 1e-3, 1e4, "z_rand_range_m"); !s.ok()) return s;
  if (absl::Status s = CheckRange(max_distance_m, 1e-3, 100.0, "max_distance_m"); !s.ok()) {
    return s;
  }
  if (absl::Status s = CheckRange(sigma_free_m, 1e-4, 10.0, "sigma_free_m"); !s.ok()) return s;
  if (absl::Status s = CheckRange(no_echo_floor, 1e-9, 1.0, "no_echo_floor"); !s.ok()) return s;
  if (absl::Status s = CheckRange(free_step_m, 1e-3, 10.0, "free_step_m"); !s.ok()) return s;
  return CheckRange(beam_exponent, 1e-6, 1.0, "beam_exponent");
}

absl::StatusOr<LikelihoodField> LikelihoodField::Create(const OccupancyGrid& grid,
                                                        const LikelihoodFieldParams& params) {
  if (absl::Status s = params.Validate(); !s.ok()) return s;
  if (grid.origin().yaw_rad() != 0.0) {
    return absl::InvalidArgumentError("grid origin yaw must be 0 for the likelihood field");
  }
  LikelihoodField field;
  field.params_ = params;
  field.width_ = grid.width();
  field.height_ = grid.height();
  field.width_f_ = static_cast<float>(grid.width());
  field.height_f_ = static_cast<float>(grid.height());
  field.origin_x_ = static_cast<float>(grid.origin().x_m());
  field.origin_y_ = static_cast<float>(grid.origin().y_m());
  field.inv_resolution_ = static_cast<float>(1.0 / grid.resolution_m());
  const size_t cells = static_cast<size_t>(grid.width()) * grid.height();
  field.outside_ = cells;

  // Exact squared distance (in cells) to the nearest obstacle surface — an occupied cell with a
  // side on a cell that is not (or on the map's edge) — columns, then rows. An echo comes off a
  // surface: an end point inside a solid box or a thick wall is as far from where the echo
  // could have come as one in front of it (measured to any occupied cell, a particle too near a
  // box would fit every range, and the estimate could drift into the box unchecked).
  const int w = grid.width();
  const int h = grid.height();
  const auto occupied = [&](int x, int y) {
    return grid.InBounds(CellIndex{x, y}) && grid.State(CellIndex{x, y}) == CellState::kOccupied;
  };
  std::vector<double> squared(cells, kFar);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (occupied(x, y) &&
          !(occupied(x - 1, y) && occupied(x + 1, y) && occupied(x, y - 1) && occupied(x, y + 1))) {
        squared[static_cast<size_t>(y) * w + x] = 0.0;
      }
    }
  }
  {
    const int n = std::max(w, h);
    std::vector<double> f(n), d(n), z(n + 1);
    std::vector<int> v(n);
    f.resize(h);
    d.resize(h);
    for (int x = 0; x < w; ++x) {
      for (int y = 0; y < h; ++y) f[y] = squared[static_cast<size_t>(y) * w + x];
      SquaredDistanceTransform1d(f.data(), static_cast<int>(f.size()), d.data(), v.data(),
                                 z.data());
      for (int y = 0; y < h; ++y) squared[static_cast<size_t>(y) * w + x] = d[y];
    }
    f.resize(w);
    d.resize(w);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) f[x] = squared[static_cast<size_t>(y) * w + x];
      SquaredDistanceTransform1d(f.data(), static_cast<int>(f.size()), d.data(), v.data(),
                                 z.data());
      for (int x = 0; x < w; ++x) squared[static_cast<size_t>(y) * w + x] = d[x];
    }
  }

  const double rand_term = params.z_rand / params.z_rand_range_m;
  const auto log_hit = [&](double d) {
    return std::log(params.z_hit *
                        std::exp(-d * d / (2.0 * params.sigma_hit_m * params.sigma_hit_m)) +
                    rand_term);
  };
  const auto log_free = [&](double d) {
    const double miss = 1.0 - std::exp(-d * d / (2.0 * params.sigma_free_m * params.sigma_free_m));
    return std::log(params.no_echo_floor + (1.0 - params.no_echo_floor) * miss);
  };
  field.log_hit_.resize(cells + 1);
  field.log_free_.resize(cells + 1);
  field.distance_m_.resize(cells + 1);
  for (size_t i = 0; i < cells; ++i) {
    const double d = std::min(std::sqrt(squared[i]) * grid.resolution_m(), params.max_distance_m);
    const int x = static_cast<int>(i % w);
    const int y = static_cast<int>(i / w);
    const bool unknown = grid.State(CellIndex{x, y}) == CellState::kUnknown;
    field.distance_m_[i] = static_cast<float>(d);
    field.log_hit_[i] = static_cast<float>(unknown ? std::log(rand_term) : log_hit(d));
    field.log_free_[i] = static_cast<float>(log_free(d));
  }
  field.distance_m_[cells] = static_cast<float>(params.max_distance_m);
  field.log_hit_[cells] = static_cast<float>(std::log(rand_term));
  field.log_free_[cells] = 0.0f;
  field.max_log_hit_ = static_cast<float>(log_hit(0.0));
  return field;
}

size_t LikelihoodField::MemoryBytes() const {
  return (log_hit_.size() + log_free_.size() + distance_m_.size()) * sizeof(float);
}

int LikelihoodField::Accumulate(const RangeObservation& observation, const float* x, const float* y,
                                const float* yaw, size_t n, float* log_weight) const {
  // End points (echo beams: one per ray of a cone, the best of them counts) and free-path
  // sample points (no-echo beams) in base_link.
  std::vector<float> hit_x, hit_y;
  std::vector<int> hit_begin;
  std::vector<float> free_x, free_y;
  std::vector<int> free_begin;
  for (const RangeBeam& beam : observation.beams) {
    if (!beam.no_echo) {
      hit_begin.push_back(static_cast<int>(hit_x.size()));
      for (double angle : BeamRayAngles(beam)) {
        hit_x.push_back(
            static_cast<float>(beam.origin_in_base.x() + std::cos(angle) * beam.range_m));
        hit_y.push_back(
            static_cast<float>(beam.origin_in_base.y() + std::sin(angle) * beam.range_m));
      }
      continue;
    }
    const double c = std::cos(beam.angle_in_base_rad);
    const double s = std::sin(beam.angle_in_base_rad);
    free_begin.push_back(static_cast<int>(free_x.size()));
    for (double r = params_.free_step_m; r <= beam.range_max_m + 1e-9; r += params_.free_step_m) {
      free_x.push_back(static_cast<float>(beam.origin_in_base.x() + c * r));
      free_y.push_back(static_cast<float>(beam.origin_in_base.y() + s * r));
    }
  }
  free_begin.push_back(static_cast<int>(free_x.size()));
  hit_begin.push_back(static_cast<int>(hit_x.size()));
  const size_t hits = hit_begin.size() - 1;
  const size_t free_beams = free_begin.size() - 1;
  const float exponent = static_cast<float>(params_.beam_exponent);
  const float* hx = hit_x.data();
  const float* hy = hit_y.data();
  for (size_t i = 0; i < n; ++i) {
    const float c = std::cos(yaw[i]);
    const float s = std::sin(yaw[i]);
    const float px = x[i];
    const float py = y[i];
    float sum = 0.0f;
    for (size_t b = 0; b < hits; ++b) {
      float best = -std::numeric_limits<float>::infinity();
      for (int k = hit_begin[b]; k < hit_begin[b + 1]; ++k) {
        best = std::max(best, LogHit(px + c * hx[k] - s * hy[k], py + s * hx[k] + c * hy[k]));
      }
      sum += best;
    }
    for (size_t b = 0; b < free_beams; ++b) {
      float worst = 0.0f;
      for (int k = free_begin[b]; k < free_begin[b + 1]; ++k) {
        worst = std::min(
            worst, LogFree(px + c * free_x[k] - s * free_y[k], py + s * free_x[k] + c * free_y[k]));
      }
      sum += worst;
    }
    log_weight[i] += exponent * sum;
  }
  return static_cast<int>(hits + free_beams);
}

absl::Status BeamModelParams::Validate() const {
  const std::pair<double, const char*> weights[] = {
      {z_hit, "z_hit"}, {z_short, "z_short"}, {z_max, "z_max"}, {z_rand, "z_rand"}};
  for (const auto& [value, name] : weights) {
    if (absl::Status s = CheckRange(value, 0.0, 1.0, name); !s.ok()) return s;
  }
  if (z_rand <= 0.0) return absl::InvalidArgumentError("z_rand must be > 0");
  if (absl::Status s = CheckRange(sigma_hit_m, 1e-4, 10.0, "sigma_hit_m"); !s.ok()) return s;
  if (absl::Status s = CheckRange(lambda_short, 1e-6, 1e3, "lambda_short"); !s.ok()) return s;
  return CheckRange(beam_exponent, 1e-6, 1.0, "beam_exponent");
}

double CastRay(const OccupancyGrid& grid, const Eigen::Vector2d& origin, double angle_rad,
               double range_max_m) {
  const Eigen::Vector2d p = grid.origin().Inverse().TransformPoint(origin);
  const double dir_angle = angle_rad - grid.origin().yaw_rad();
  const double dx = std::cos(dir_angle);
  const double dy = std::sin(dir_angle);
  const double res = grid.resolution_m();
  double fx = p.x() / res;
  double fy = p.y() / res;
  int cx = static_cast<int>(std::floor(fx));
  int cy = static_cast<int>(std::floor(fy));
  const int step_x = dx > 0 ? 1 : -1;
  const int step_y = dy > 0 ? 1 : -1;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const double t_delta_x = dx != 0.0 ? std::abs(1.0 / dx) * res : kInf;
  const double t_delta_y = dy != 0.0 ? std::abs(1.0 / dy) * res : kInf;
  double t_max_x = dx != 0.0 ? ((dx > 0 ? (cx + 1 - fx) : (fx - cx)) * res) / std::abs(dx) : kInf;
  double t_max_y = dy != 0.0 ? ((dy > 0 ? (cy + 1 - fy) : (fy - cy)) * res) / std::abs(dy) : kInf;
  double t = 0.0;
  while (t <= range_max_m) {
    const CellIndex cell{cx, cy};
    if (!grid.InBounds(cell)) return range_max_m;
    if (grid.State(cell) == CellState::kOccupied) return std::min(t, range_max_m);
    if (t_max_x < t_max_y) {
      t = t_max_x;
      t_max_x += t_delta_x;
      cx += step_x;
    } else {
      t = t_max_y;
      t_max_y += t_delta_y;
      cy += step_y;
    }
  }
  return range_max_m;
}

double BeamModel::LogLikelihood(double measured_m, double expected_m, double range_max_m,
                                bool no_echo) const {
  const BeamModelParams& p = params_;
  double prob = 0.0;
  if (no_echo) {
    // p(z = z_max): the max-range spike, plus the hit mass beyond range when nothing is there.
    prob = p.z_max + (expected_m >= range_max_m ? p.z_hit : 0.0);
  } else {
    const double z = measured_m - expected_m;
    prob += p.z_hit * std::exp(-z * z / (2.0 * p.sigma_hit_m * p.sigma_hit_m)) /
            (p.sigma_hit_m * std::sqrt(2.0 * kPi));
    if (measured_m < expected_m) {
      prob += p.z_short * p.lambda_short * std::exp(-p.lambda_short * measured_m);
    }
    prob += p.z_rand / range_max_m;
  }
  return std::log(std::max(prob, 1e-12));
}

int BeamModel::Accumulate(const RangeObservation& observation, const float* x, const float* y,
                          const float* yaw, size_t n, float* log_weight) const {
  std::vector<std::vector<double>> ray_angles;  // per beam, once for every particle
  ray_angles.reserve(observation.beams.size());
  for (const RangeBeam& beam : observation.beams) ray_angles.push_back(BeamRayAngles(beam));
  for (size_t i = 0; i < n; ++i) {
    const Pose2 pose(x[i], y[i], yaw[i]);
    double sum = 0.0;
    for (size_t b = 0; b < observation.beams.size(); ++b) {
      const RangeBeam& beam = observation.beams[b];
      const Eigen::Vector2d origin = pose.TransformPoint(beam.origin_in_base);
      double expected = beam.range_max_m;  // the nearest surface in the cone echoes
      for (double angle : ray_angles[b]) {
        expected =
            std::min(expected, CastRay(grid_, origin, pose.yaw_rad() + angle, beam.range_max_m));
      }
      sum += LogLikelihood(beam.range_m, expected, beam.range_max_m, beam.no_echo);
    }
    log_weight[i] += static_cast<float>(params_.beam_exponent * sum);
  }
  return static_cast<int>(observation.beams.size());
}

}  // namespace fleetnav::localization
