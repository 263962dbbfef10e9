#include "fleetnav/localization/amcl.hpp"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"

namespace fleetnav::localization {
namespace {

absl::Status InRange(double value, double lo, double hi, const char* field) {
  if (std::isfinite(value) && value >= lo && value <= hi) return absl::OkStatus();
  return absl::InvalidArgumentError(
      absl::StrCat(field, " must be in [", lo, ", ", hi, "], got ", value));
}

float WrapYaw(double yaw) { return static_cast<float>(NormalizeAngle(yaw)); }

}  // namespace

absl::Status AmclParams::Validate() const {
  if (min_particles < 1 || max_particles < min_particles || max_particles > 10'000'000) {
    return absl::InvalidArgumentError(
        absl::StrCat("need 1 <= min_particles <= max_particles <= 1e7, got ", min_particles,
                     " and ", max_particles));
  }
  const struct {
    double value, lo, hi;
    const char* name;
  } checks[] = {
      {kld_epsilon, 1e-6, 1.0, "kld_epsilon"},
      {kld_delta, 1e-9, 0.5, "kld_delta"},
      {kld_bin_xy_m, 1e-3, 100.0, "kld_bin_xy_m"},
      {kld_bin_yaw_rad, 1e-3, 2.0 * kPi, "kld_bin_yaw_rad"},
      {resample_neff_ratio, 0.0, 1.0, "resample_neff_ratio"},
      {alpha_slow, 0.0, 1.0, "alpha_slow"},
      {alpha_fast, 0.0, 1.0, "alpha_fast"},
      {recovery_min_probability, 0.0, 1.0, "recovery_min_probability"},
      {update_min_distance_m, 0.0, 100.0, "update_min_distance_m"},
      {update_min_angle_rad, 0.0, 2.0 * kPi, "update_min_angle_rad"},
      {stationary_update_period_s, 0.0, 3600.0, "stationary_update_period_s"},
      {cluster_bin_xy_m, 1e-3, 100.0, "cluster_bin_xy_m"},
      {cluster_bin_yaw_rad, 1e-3, 2.0 * kPi, "cluster_bin_yaw_rad"},
      {lost_likelihood_score, 0.0, 1.0, "lost_likelihood_score"},
      {lost_position_stddev_m, 0.0, 1e4, "lost_position_stddev_m"},
      {lost_obstacle_distance_m, 0.0, 1e4, "lost_obstacle_distance_m"},
      {roughening_stddev_m, 0.0, 10.0, "roughening_stddev_m"},
      {roughening_stddev_rad, 0.0, kPi, "roughening_stddev_rad"},
      {roughening_below_score, 0.0, 1.0, "roughening_below_score"},
      {confidence_stddev_m, 1e-6, 1e4, "confidence_stddev_m"},
      {tempering_min_ess_ratio, 0.0, 1.0, "tempering_min_ess_ratio"},
      {reference_likelihood_score, 0.0, 1.0, "reference_likelihood_score"},
      {max_injection_fraction, 0.0, 1.0, "max_injection_fraction"},
      {converged_cluster_weight, 0.0, 1.0, "converged_cluster_weight"},
  };
  for (const auto& c : checks) {
    if (absl::Status s = InRange(c.value, c.lo, c.hi, c.name); !s.ok()) return s;
  }
  if (alpha_slow >= alpha_fast && alpha_fast > 0.0) {
    return absl::InvalidArgumentError("alpha_slow must be < alpha_fast");
  }
  if (lost_min_updates < 1) return absl::InvalidArgumentError("lost_min_updates must be >= 1");
  if (absl::Status s = motion.Validate(); !s.ok()) return s;
  if (absl::Status s = likelihood_field.Validate(); !s.ok()) return s;
  return beam.Validate();
}

absl::StatusOr<Amcl> Amcl::Create(const AmclParams& params, const OccupancyGrid& map) {
  if (absl::Status s = params.Validate(); !s.ok()) return s;
  absl::StatusOr<LikelihoodField> field = LikelihoodField::Create(map, params.likelihood_field);
  if (!field.ok()) return field.status();
  std::unique_ptr<BeamModel> beam;
  if (params.sensor_model == SensorModelType::kBeam) {
    beam = std::make_unique<BeamModel>(map, params.beam);
  }
  Amcl amcl(params, std::make_unique<LikelihoodField>(*std::move(field)), std::move(beam), map);
  if (amcl.free_cells_.empty()) {
    return absl::InvalidArgumentError("map has no free cell to localize in");
  }
  return amcl;
}

Amcl::Amcl(const AmclParams& params, std::unique_ptr<LikelihoodField> field,
           std::unique_ptr<BeamModel> beam, const OccupancyGrid& map)
    : params_(params),
      field_(std::move(field)),
      beam_(std::move(beam)),
      map_resolution_m_(map.resolution_m()),
      map_origin_(map.origin()),
      map_width_(map.width()),
      rng_(params.seed) {
  for (int y = 0; y < map.height(); ++y) {
    for (int x = 0; x < map.width(); ++x) {
      if (map.State(CellIndex{x, y}) == CellState::kFree) {
        free_cells_.push_back(static_cast<uint32_t>(y * map.width() + x));
      }
    }
  }
  particles_.Reserve(params.max_particles);
}

Pose2 Amcl::RandomFreePose() {
  const uint32_t cell = free_cells_[rng_.UniformInt(free_cells_.size())];
  const double gx = (cell % map_width_ + rng_.Uniform()) * map_resolution_m_;
  const double gy = (cell / map_width_ + rng_.Uniform()) * map_resolution_m_;
  const Eigen::Vector2d p = map_origin_.TransformPoint({gx, gy});
  return Pose2(p.x(), p.y(), (2.0 * rng_.Uniform() - 1.0) * kPi);
}

absl::Status Amcl::InitializePose(const Pose2& pose_in_map, const Eigen::Vector3d& stddev,
                                  const Pose2& pose_in_odom, int64_t stamp_ns) {
  if (!pose_in_map.IsFinite() || !pose_in_odom.IsFinite()) {
    return absl::InvalidArgumentError("initial poses must be finite");
  }
  if (!stddev.allFinite() || (stddev.array() < 0.0).any()) {
    return absl::InvalidArgumentError("stddev must be finite and >= 0");
  }
  const size_t n = params_.max_particles;
  particles_.Resize(n);
  for (size_t i = 0; i < n; ++i) {
    particles_.x_m[i] = static_cast<float>(pose_in_map.x_m() + stddev.x() * rng_.Normal());
    particles_.y_m[i] = static_cast<float>(pose_in_map.y_m() + stddev.y() * rng_.Normal());
    particles_.yaw_rad[i] = WrapYaw(pose_in_map.yaw_rad() + stddev.z() * rng_.Normal());
  }
  particles_.SetUniformWeights();
  filter_odom_ = pose_in_odom;
  initialized_ = true;
  force_update_ = true;
  w_slow_ = w_fast_ = 0.0;
  low_score_updates_ = 0;
  impossible_place_updates_ = 0;
  RecomputeEstimate(stamp_ns);
  return absl::OkStatus();
}

absl::Status Amcl::InitializeGlobal(const Pose2& pose_in_odom, int64_t stamp_ns) {
  if (!pose_in_odom.IsFinite()) return absl::InvalidArgumentError("pose_in_odom must be finite");
  const size_t n = params_.max_particles;
  particles_.Resize(n);
  for (size_t i = 0; i < n; ++i) {
    const Pose2 p = RandomFreePose();
    particles_.x_m[i] = static_cast<float>(p.x_m());
    particles_.y_m[i] = static_cast<float>(p.y_m());
    particles_.yaw_rad[i] = static_cast<float>(p.yaw_rad());
  }
  particles_.SetUniformWeights();
  filter_odom_ = pose_in_odom;
  initialized_ = true;
  force_update_ = true;
  w_slow_ = w_fast_ = 0.0;
  low_score_updates_ = 0;
  impossible_place_updates_ = 0;
  RecomputeEstimate(stamp_ns);
  return absl::OkStatus();
}

absl::Status Amcl::Predict(const Pose2& pose_in_odom) {
  if (!initialized_) return absl::FailedPreconditionError("AMCL is not initialized");
  if (!pose_in_odom.IsFinite()) return absl::InvalidArgumentError("pose_in_odom must be finite");
  SampleMotion(params_.motion, filter_odom_, pose_in_odom, rng_, particles_.x_m.data(),
               particles_.y_m.data(), particles_.yaw_rad.data(), particles_.size());
  filter_odom_ = pose_in_odom;
  return absl::OkStatus();
}

absl::StatusOr<bool> Amcl::PredictIfMoved(const Pose2& pose_in_odom) {
  if (!initialized_) return absl::FailedPreconditionError("AMCL is not initialized");
  const double moved_m = (pose_in_odom.translation() - filter_odom_.translation()).norm();
  const double turned_rad =
      std::abs(AngleDifference(pose_in_odom.yaw_rad(), filter_odom_.yaw_rad()));
  if (moved_m < params_.update_min_distance_m && turned_rad < params_.update_min_angle_rad) {
    return false;
  }
  if (absl::Status s = Predict(pose_in_odom); !s.ok()) return s;
  // No range reading to weigh by: the estimate's place alone can still show it wrong.
  CountPlace(PoseInMap(pose_in_odom));
  return true;
}

void Amcl::Weigh(const RangeObservation& observation) {
  const size_t n = particles_.size();
  std::fill(particles_.log_likelihood.begin(), particles_.log_likelihood.end(), 0.0f);
  int beams = 0;
  if (beam_ != nullptr) {
    beams = beam_->Accumulate(observation, particles_.x_m.data(), particles_.y_m.data(),
                              particles_.yaw_rad.data(), n, particles_.log_likelihood.data());
  } else {
    beams = field_->Accumulate(observation, particles_.x_m.data(), particles_.y_m.data(),
                               particles_.yaw_rad.data(), n, particles_.log_likelihood.data());
  }
  stats_.sensor_update = true;
  if (beams == 0 || n == 0) return;
  float max_ll = -std::numeric_limits<float>::infinity();
  for (float ll : particles_.log_likelihood) max_ll = std::max(max_ll, ll);
  double lambda = 1.0;
  const bool uncertain = GloballyUncertain();
  if (params_.tempering_min_ess_ratio > 0.0 && uncertain) {
    // Largest λ with N_eff(w·L^λ) ≥ ratio·N, by bisection on λ (N_eff falls as λ grows).
    const auto ess = [&](double l) {
      double sum = 0.0, sq = 0.0;
      for (size_t i = 0; i < n; ++i) {
        const double w = particles_.weight[i] *
                         std::exp(l * static_cast<double>(particles_.log_likelihood[i] - max_ll));
        sum += w;
        sq += w * w;
      }
      return sq > 0.0 ? sum * sum / sq : 0.0;
    };
    const double floor = params_.tempering_min_ess_ratio * static_cast<double>(n);
    if (ess(1.0) < floor) {
      double lo = 0.0, hi = 1.0;
      for (int it = 0; it < 12; ++it) {
        const double mid = 0.5 * (lo + hi);
        (ess(mid) >= floor ? lo : hi) = mid;
      }
      lambda = std::max(lo, 1e-6);
    }
  }
  stats_.tempering = lambda;
  double total = 0.0;
  for (size_t i = 0; i < n; ++i) {
    particles_.weight[i] *=
        std::exp(lambda * static_cast<double>(particles_.log_likelihood[i] - max_ll));
    total += particles_.weight[i];
  }
  if (!(total > 0.0) || !std::isfinite(total)) {
    particles_.SetUniformWeights();
    return;
  }
  for (double& w : particles_.weight) w /= total;
  // Per-beam geometric-mean likelihood of the weighted set, relative to the best a beam can
  // score: a number in (0, 1] that does not underflow with many beams.
  const double log_avg = (std::log(total) + lambda * max_ll) / lambda;
  const double exponent =
      beam_ != nullptr ? params_.beam.beam_exponent : params_.likelihood_field.beam_exponent;
  const BeamModelParams& bp = params_.beam;
  const double best = beam_ != nullptr
                          ? std::log(bp.z_hit / (bp.sigma_hit_m * std::sqrt(2.0 * kPi)) + bp.z_rand)
                          : static_cast<double>(field_->max_log_hit());
  last_score_ = std::min(1.0, std::exp(log_avg / (beams * exponent) - best));
  if (uncertain && w_slow_ == 0.0) {
    // Until the filter first converges the averages are not started: their reference must be
    // the likelihood of a converged filter, or a wrong mode would look normal. Once started
    // they keep running through recovery, so injection continues until the scans fit again.
  } else if (w_slow_ == 0.0) {
    // First converged measurement: start the slow average at it, but never below the score a
    // converged filter should reach, so that converging onto a wrong mode of a near-symmetric
    // map still triggers recovery (starting at 0, as ROS amcl does, would hide it).
    w_slow_ = std::max(last_score_, params_.reference_likelihood_score);
    w_fast_ = last_score_;
  } else {
    w_slow_ += params_.alpha_slow * (last_score_ - w_slow_);
    w_fast_ += params_.alpha_fast * (last_score_ - w_fast_);
  }
}

bool Amcl::GloballyUncertain() const {
  return health_.position_stddev_m > params_.lost_position_stddev_m ||
         estimate_.cluster_weight < params_.converged_cluster_weight;
}

void Amcl::Resample() {
  const size_t n = particles_.size();
  stats_.effective_sample_size = EffectiveSampleSize(particles_.weight);
  const double p_inject =
      w_slow_ > 0.0 ? std::clamp(1.0 - w_fast_ / w_slow_, 0.0, params_.max_injection_fraction)
                    : 0.0;
  stats_.injection_probability = p_inject;
  const bool recover = p_inject > params_.recovery_min_probability;
  if (!recover && stats_.effective_sample_size >= params_.resample_neff_ratio * n) return;

  size_t target = n;
  if (params_.min_particles != params_.max_particles) {
    // KLD-sampling: the support of the resampled set decides the size of the next one.
    SystematicResample(particles_.weight, n, rng_, indices_);
    ParticleSet& p = particles_;
    p.next_x_m.resize(n);
    p.next_y_m.resize(n);
    p.next_yaw_rad.resize(n);
    size_t w = 0;
    for (size_t m = 0; m < n; ++m) {
      if (m > 0 && indices_[m] == indices_[m - 1]) continue;
      p.next_x_m[w] = p.x_m[indices_[m]];
      p.next_y_m[w] = p.y_m[indices_[m]];
      p.next_yaw_rad[w] = p.yaw_rad[indices_[m]];
      ++w;
    }
    ParticleSet support;
    support.x_m.assign(p.next_x_m.begin(), p.next_x_m.begin() + w);
    support.y_m.assign(p.next_y_m.begin(), p.next_y_m.begin() + w);
    support.yaw_rad.assign(p.next_yaw_rad.begin(), p.next_yaw_rad.begin() + w);
    size_t bins = CountOccupiedBins(support, params_.kld_bin_xy_m, params_.kld_bin_yaw_rad);
    if (recover) bins = std::max(bins, static_cast<size_t>(p_inject * params_.max_particles));
    target = std::clamp(KldSampleCount(bins, params_.kld_epsilon, params_.kld_delta),
                        params_.min_particles, params_.max_particles);
  }
  SystematicResample(particles_.weight, target, rng_, indices_);
  ParticleSet& p = particles_;
  p.next_x_m.resize(target);
  p.next_y_m.resize(target);
  p.next_yaw_rad.resize(target);
  size_t injected = 0;
  for (size_t m = 0; m < target; ++m) {
    if (recover && rng_.Uniform() < p_inject) {
      const Pose2 r = RandomFreePose();
      p.next_x_m[m] = static_cast<float>(r.x_m());
      p.next_y_m[m] = static_cast<float>(r.y_m());
      p.next_yaw_rad[m] = static_cast<float>(r.yaw_rad());
      ++injected;
      continue;
    }
    const uint32_t i = indices_[m];
    p.next_x_m[m] = p.x_m[i];
    p.next_y_m[m] = p.y_m[i];
    p.next_yaw_rad[m] = p.yaw_rad[i];
  }
  p.x_m.swap(p.next_x_m);
  p.y_m.swap(p.next_y_m);
  p.yaw_rad.swap(p.next_yaw_rad);
  p.weight.resize(target);
  p.log_likelihood.resize(target);
  p.SetUniformWeights();
  stats_.resampled = true;
  stats_.injected = injected;
}

void Amcl::RecomputeEstimate(int64_t stamp_ns) {
  const std::vector<ClusterEstimate> clusters =
      ClusterParticles(particles_, params_.cluster_bin_xy_m, params_.cluster_bin_yaw_rad);
  double total = 0.0;
  for (double w : particles_.weight) total += w;
  if (!clusters.empty()) {
    estimate_.pose_in_map = clusters.front().mean;
    estimate_.covariance = clusters.front().covariance;
    estimate_.cluster_weight = total > 0.0 ? clusters.front().weight / total : 0.0;
  }
  estimate_.cluster_count = clusters.size();
  estimate_.particle_count = particles_.size();
  estimate_.stamp_ns = stamp_ns;
  estimate_.map_to_odom = estimate_.pose_in_map * filter_odom_.Inverse();
  UpdateHealth(stamp_ns);
}

void Amcl::UpdateHealth(int64_t /*stamp_ns*/) {
  const Eigen::Matrix3d& c = estimate_.covariance;
  health_.position_stddev_m = std::sqrt(std::max(0.0, c(0, 0) + c(1, 1)));
  health_.yaw_stddev_rad = std::sqrt(std::max(0.0, c(2, 2)));
  health_.likelihood_score = std::clamp(last_score_, 0.0, 1.0);
  const double spread = std::exp(-health_.position_stddev_m / params_.confidence_stddev_m);
  health_.confidence =
      std::clamp(health_.likelihood_score * spread * estimate_.cluster_weight, 0.0, 1.0);
  CountPlace(estimate_.pose_in_map);
}

void Amcl::CountPlace(const Pose2& pose_in_map) {
  const auto x = static_cast<float>(pose_in_map.x_m());
  const auto y = static_cast<float>(pose_in_map.y_m());
  const bool impossible_place =
      !field_->Contains(x, y) || field_->DistanceM(x, y) < params_.lost_obstacle_distance_m;
  impossible_place_updates_ = impossible_place ? impossible_place_updates_ + 1 : 0;
  health_.lost_reason.clear();
  if (low_score_updates_ >= params_.lost_min_updates) {
    health_.lost_reason = absl::StrFormat("the map has explained no range reading for %d updates",
                                          low_score_updates_);
  } else if (impossible_place_updates_ >= params_.lost_min_updates) {
    health_.lost_reason = absl::StrFormat(
        "the estimate (%.2f, %.2f) has been off the map or inside an obstacle for %d updates",
        pose_in_map.x_m(), pose_in_map.y_m(), impossible_place_updates_);
  } else if (health_.position_stddev_m > params_.lost_position_stddev_m) {
    health_.lost_reason =
        absl::StrFormat("the particle cloud is %.2f m wide (limit %.2f m)",
                        health_.position_stddev_m, params_.lost_position_stddev_m);
  }
  health_.lost = !health_.lost_reason.empty();
}

absl::StatusOr<bool> Amcl::Update(const Pose2& pose_in_odom, const RangeObservation& observation,
                                  int64_t stamp_ns) {
  if (!initialized_) return absl::FailedPreconditionError("AMCL is not initialized");
  if (!pose_in_odom.IsFinite()) return absl::InvalidArgumentError("pose_in_odom must be finite");
  stats_ = AmclUpdateStats{};
  const double moved_m = (pose_in_odom.translation() - filter_odom_.translation()).norm();
  const double turned_rad =
      std::abs(AngleDifference(pose_in_odom.yaw_rad(), filter_odom_.yaw_rad()));
  const bool moved =
      moved_m >= params_.update_min_distance_m || turned_rad >= params_.update_min_angle_rad;
  const bool stationary_due = params_.stationary_update_period_s > 0.0 &&
                              static_cast<double>(stamp_ns - last_sensor_update_ns_) * 1e-9 >=
                                  params_.stationary_update_period_s;
  if (!(moved || stationary_due || force_update_)) return false;
  force_update_ = false;
  if (absl::Status s = Predict(pose_in_odom); !s.ok()) return s;
  last_sensor_update_ns_ = stamp_ns;
  Weigh(observation);
  if (last_score_ < params_.lost_likelihood_score) {
    ++low_score_updates_;
  } else {
    low_score_updates_ = 0;
  }
  Resample();
  // Only after travel: turning in place, two beams sweep across surfaces at grazing angles and
  // fit badly for a while without the position being in doubt.
  if (last_score_ < params_.roughening_below_score && moved_m >= params_.update_min_distance_m) {
    Roughen();
  }
  RecomputeEstimate(stamp_ns);
  return true;
}

void Amcl::Roughen() {
  if (params_.roughening_stddev_m <= 0.0 && params_.roughening_stddev_rad <= 0.0) return;
  ParticleSet& p = particles_;
  for (size_t i = 0; i < p.size(); ++i) {
    p.x_m[i] += static_cast<float>(params_.roughening_stddev_m * rng_.Normal());
    p.y_m[i] += static_cast<float>(params_.roughening_stddev_m * rng_.Normal());
    p.yaw_rad[i] += static_cast<float>(params_.roughening_stddev_rad * rng_.Normal());
  }
}

}  // namespace fleetnav::localization
