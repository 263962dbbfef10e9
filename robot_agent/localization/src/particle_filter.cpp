#include "fleetnav/localization/particle_filter.hpp"

#include <algorithm>
#include <cmath>
#include <deque>

#include "absl/container/flat_hash_map.h"
#include "absl/container/flat_hash_set.h"
#include "fleetnav/core/angles.hpp"

namespace fleetnav::localization {
namespace {

struct BinKey {
  int32_t x, y, yaw;
  bool operator==(const BinKey&) const = default;
  template <typename H>
  friend H AbslHashValue(H h, const BinKey& k) {
    return H::combine(std::move(h), k.x, k.y, k.yaw);
  }
};

BinKey BinOf(float x, float y, float yaw, double inv_xy, double inv_yaw, int yaw_bins) {
  int by = static_cast<int>(std::floor((yaw + kPi) * inv_yaw));
  if (by >= yaw_bins) by = yaw_bins - 1;
  if (by < 0) by = 0;
  return {static_cast<int32_t>(std::floor(x * inv_xy)),
          static_cast<int32_t>(std::floor(y * inv_xy)), by};
}

ClusterEstimate Summarise(const ParticleSet& p, const std::vector<uint32_t>& members) {
  ClusterEstimate e;
  double w_sum = 0.0, mx = 0.0, my = 0.0, mc = 0.0, ms = 0.0;
  for (uint32_t i : members) {
    const double w = p.weight[i];
    w_sum += w;
    mx += w * p.x_m[i];
    my += w * p.y_m[i];
    mc += w * std::cos(p.yaw_rad[i]);
    ms += w * std::sin(p.yaw_rad[i]);
  }
  e.weight = w_sum;
  e.particle_count = members.size();
  if (w_sum <= 0.0) return e;
  mx /= w_sum;
  my /= w_sum;
  const double myaw = std::atan2(ms, mc);
  e.mean = Pose2(mx, my, myaw);
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (uint32_t i : members) {
    const Eigen::Vector3d d(p.x_m[i] - mx, p.y_m[i] - my, AngleDifference(p.yaw_rad[i], myaw));
    cov += p.weight[i] * d * d.transpose();
  }
  e.covariance = cov / w_sum;
  return e;
}

}  // namespace

void ParticleSet::Resize(size_t n) {
  x_m.resize(n);
  y_m.resize(n);
  yaw_rad.resize(n);
  weight.resize(n);
  log_likelihood.resize(n);
}

void ParticleSet::Reserve(size_t n) {
  for (auto* v : {&x_m, &y_m, &yaw_rad, &log_likelihood, &next_x_m, &next_y_m, &next_yaw_rad}) {
    v->reserve(n);
  }
  weight.reserve(n);
}

void ParticleSet::SetUniformWeights() {
  std::fill(weight.begin(), weight.end(), weight.empty() ? 0.0 : 1.0 / weight.size());
}

size_t KldSampleCount(size_t occupied_bins, double epsilon, double delta) {
  if (occupied_bins <= 1) return 1;
  const double k = static_cast<double>(occupied_bins - 1);
  const double z = NormalQuantile(1.0 - delta);
  const double a = 2.0 / (9.0 * k);
  const double b = 1.0 - a + std::sqrt(a) * z;
  return static_cast<size_t>(std::ceil(k / (2.0 * epsilon) * b * b * b));
}

double EffectiveSampleSize(const std::vector<double>& weight) {
  double sum = 0.0, sq = 0.0;
  for (double w : weight) {
    sum += w;
    sq += w * w;
  }
  return sq > 0.0 ? sum * sum / sq : 0.0;
}

void SystematicResample(const std::vector<double>& weight, size_t count, Rng& rng,
                        std::vector<uint32_t>& indices) {
  indices.resize(count);
  double total = 0.0;
  for (double w : weight) total += w;
  const double step = total / static_cast<double>(count);
  double target = rng.Uniform() * step;
  double cumulative = weight.empty() ? 0.0 : weight[0];
  size_t i = 0;
  const size_t last = weight.size() - 1;
  for (size_t m = 0; m < count; ++m) {
    while (target > cumulative && i < last) cumulative += weight[++i];
    indices[m] = static_cast<uint32_t>(i);
    target += step;
  }
}

size_t CountOccupiedBins(const ParticleSet& p, double bin_xy_m, double bin_yaw_rad) {
  const int yaw_bins = std::max(1, static_cast<int>(std::ceil(2.0 * kPi / bin_yaw_rad)));
  absl::flat_hash_set<BinKey> bins;
  bins.reserve(std::min<size_t>(p.size(), 1 << 16));
  const double inv_xy = 1.0 / bin_xy_m;
  const double inv_yaw = 1.0 / bin_yaw_rad;
  for (size_t i = 0; i < p.size(); ++i) {
    bins.insert(BinOf(p.x_m[i], p.y_m[i], p.yaw_rad[i], inv_xy, inv_yaw, yaw_bins));
  }
  return bins.size();
}

std::vector<ClusterEstimate> ClusterParticles(const ParticleSet& p, double bin_xy_m,
                                              double bin_yaw_rad) {
  const int yaw_bins = std::max(1, static_cast<int>(std::ceil(2.0 * kPi / bin_yaw_rad)));
  const double inv_xy = 1.0 / bin_xy_m;
  const double inv_yaw = 1.0 / bin_yaw_rad;
  absl::flat_hash_map<BinKey, int> bin_index;
  std::vector<std::vector<uint32_t>> bin_members;
  std::vector<BinKey> keys;
  for (size_t i = 0; i < p.size(); ++i) {
    const BinKey key = BinOf(p.x_m[i], p.y_m[i], p.yaw_rad[i], inv_xy, inv_yaw, yaw_bins);
    auto [it, inserted] = bin_index.try_emplace(key, static_cast<int>(keys.size()));
    if (inserted) {
      keys.push_back(key);
      bin_members.emplace_back();
    }
    bin_members[it->second].push_back(static_cast<uint32_t>(i));
  }
  // Connected components over the 26-neighbourhood (yaw wraps around).
  std::vector<int> label(keys.size(), -1);
  std::vector<ClusterEstimate> clusters;
  std::vector<uint32_t> members;
  std::vector<int> stack;
  for (size_t start = 0; start < keys.size(); ++start) {
    if (label[start] >= 0) continue;
    const int id = static_cast<int>(clusters.size());
    members.clear();
    stack.assign(1, static_cast<int>(start));
    label[start] = id;
    while (!stack.empty()) {
      const int b = stack.back();
      stack.pop_back();
      members.insert(members.end(), bin_members[b].begin(), bin_members[b].end());
      const BinKey k = keys[b];
      for (int dx = -1; dx <= 1; ++dx) {
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dyaw = -1; dyaw <= 1; ++dyaw) {
            const BinKey n{k.x + dx, k.y + dy, (k.yaw + dyaw + yaw_bins) % yaw_bins};
            auto it = bin_index.find(n);
            if (it == bin_index.end() || label[it->second] >= 0) continue;
            label[it->second] = id;
            stack.push_back(it->second);
          }
        }
      }
    }
    clusters.push_back(Summarise(p, members));
  }
  std::sort(clusters.begin(), clusters.end(),
            [](const ClusterEstimate& a, const ClusterEstimate& b) { return a.weight > b.weight; });
  return clusters;
}

ClusterEstimate WeightedMean(const ParticleSet& p) {
  std::vector<uint32_t> all(p.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<uint32_t>(i);
  return Summarise(p, all);
}

}  // namespace fleetnav::localization
