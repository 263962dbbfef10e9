// fleetnav-loc-bench: prints one JSON object of localization figures (issue 5, "Benchmark").
//   fleetnav-loc-bench --json                                  speed figures
//   fleetnav-loc-bench --experiment samcl-vs-amcl --seeds 20   thesis Experiment 2 figures
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "bench_world.hpp"
#include "fleetnav/core/version.hpp"
#include "fleetnav/localization/amcl.hpp"
#include "fleetnav/localization/synthetic.hpp"

namespace fleetnav::loc_bench {
namespace {

using Clock = std::chrono::steady_clock;
using localization::Amcl;
using localization::AmclParams;
using localization::RangeObservation;
using localization::Rng;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Particles clustered as when tracking: σ 10 cm, 3°, around the true pose.
void Cluster(const Pose2& truth, size_t n, Rng& rng, std::vector<float>& x, std::vector<float>& y,
             std::vector<float>& yaw) {
  x.resize(n);
  y.resize(n);
  yaw.resize(n);
  for (size_t i = 0; i < n; ++i) {
    x[i] = static_cast<float>(truth.x_m() + 0.1 * rng.Normal());
    y[i] = static_cast<float>(truth.y_m() + 0.1 * rng.Normal());
    yaw[i] = static_cast<float>(truth.yaw_rad() + 0.05 * rng.Normal());
  }
}

double WeightNsPerParticleBeam(const OccupancyGrid& map) {
  const localization::LikelihoodField field =
      *localization::LikelihoodField::Create(map, localization::LikelihoodFieldParams{});
  Rng rng(7);
  const Pose2 truth(0.0, 0.0, 0.3);
  const RangeObservation scan = localization::SimulateLaser(map, truth, 100, 15.0, 0.02, rng);
  int echoes = 0;
  for (const auto& b : scan.beams) echoes += b.no_echo ? 0 : 1;
  std::vector<float> x, y, yaw;
  const size_t n = 10000;
  Cluster(truth, n, rng, x, y, yaw);
  std::vector<float> ll(n, 0.0f);
  double best = 1e30;
  for (int rep = 0; rep < 7; ++rep) {
    const auto start = Clock::now();
    for (int k = 0; k < 10; ++k) {
      field.Accumulate(scan, x.data(), y.data(), yaw.data(), n, ll.data());
    }
    best = std::min(best, SecondsSince(start) / 10.0);
  }
  // Every beam of this scan has an echo inside the walled map.
  return best * 1e9 / (static_cast<double>(n) * std::max(echoes, 1));
}

double UpdateMs(const OccupancyGrid& map, size_t particles, int beams) {
  AmclParams params;
  params.min_particles = params.max_particles = particles;
  params.update_min_distance_m = 0.0;
  params.update_min_angle_rad = 0.0;
  params.resample_neff_ratio = 1.0;  // resample on every update: the worst case
  Amcl amcl = *Amcl::Create(params, map);
  Pose2 truth(-2.0, 0.0, 0.0);
  Pose2 odom;
  (void)amcl.InitializePose(truth, {0.1, 0.1, 0.05}, odom, 0);
  Rng rng(11);
  std::vector<RangeObservation> scans;
  std::vector<Pose2> odoms;
  for (int i = 0; i < 40; ++i) {
    truth = truth * Pose2(0.1, 0.0, 0.0);
    odom = odom * Pose2(0.1, 0.0, 0.0);
    scans.push_back(localization::SimulateLaser(map, truth, beams, 15.0, 0.02, rng));
    odoms.push_back(odom);
  }
  std::vector<double> times;
  for (size_t i = 0; i < scans.size(); ++i) {
    const auto start = Clock::now();
    (void)amcl.Update(odoms[i], scans[i], static_cast<int64_t>(i + 1) * 100'000'000);
    times.push_back(SecondsSince(start) * 1e3);
  }
  std::sort(times.begin(), times.end());
  return times[times.size() / 2];
}

double ResampleExponent() {
  std::vector<double> log_n, log_t;
  Rng rng(5);
  for (size_t n : {10'000u, 100'000u, 1'000'000u}) {
    std::vector<double> w(n);
    for (double& v : w) v = rng.Uniform();
    std::vector<uint32_t> idx;
    double best = 1e30;
    for (int rep = 0; rep < 5; ++rep) {
      const auto start = Clock::now();
      localization::SystematicResample(w, n, rng, idx);
      best = std::min(best, SecondsSince(start));
    }
    log_n.push_back(std::log(static_cast<double>(n)));
    log_t.push_back(std::log(best));
  }
  // Least-squares slope of log t against log N.
  const double k = static_cast<double>(log_n.size());
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (size_t i = 0; i < log_n.size(); ++i) {
    sx += log_n[i];
    sy += log_t[i];
    sxx += log_n[i] * log_n[i];
    sxy += log_n[i] * log_t[i];
  }
  return (k * sxy - sx * sy) / (k * sxx - sx * sx);
}

double Percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t i = std::min(v.size() - 1, static_cast<size_t>(std::ceil(q * v.size())) - 1);
  return v[i];
}

int RunSpeed() {
  absl::StatusOr<OccupancyGrid> map = BenchMap(3);
  if (!map.ok()) {
    std::fprintf(stderr, "%s\n", std::string(map.status().message()).c_str());
    return 1;
  }
  const double weight_ns = WeightNsPerParticleBeam(*map);
  const double u2k60 = UpdateMs(*map, 2000, 60);
  const double u10k60 = UpdateMs(*map, 10000, 60);
  const double u10k100 = UpdateMs(*map, 10000, 100);
  const double u100k100 = UpdateMs(*map, 100000, 100);
  const double exponent = ResampleExponent();
  // Particle arrays plus the resampling index array.
  const size_t bytes = localization::ParticleSet::kBytesPerParticle + sizeof(uint32_t);
  std::printf(
      "{\"weight_ns_per_particle_beam\": %.3f, \"update_ms_2k_60beams\": %.3f, "
      "\"update_ms_10k_60beams\": %.3f, \"update_ms_10k_100beams\": %.3f, "
      "\"update_ms_100k_100beams\": %.3f, \"resample_complexity_exponent\": %.3f, "
      "\"bytes_per_particle\": %zu}\n",
      weight_ns, u2k60, u10k60, u10k100, u100k100, exponent, bytes);
  return 0;
}

int RunExperiment(int seeds) {
  std::vector<double> after, lateral, amcl_final;
  for (int seed = 1; seed <= seeds; ++seed) {
    localization::Experiment2Params p;
    p.use_samcl = true;
    absl::StatusOr<localization::Experiment2Result> s = localization::RunExperiment2(p, seed);
    p.use_samcl = false;
    absl::StatusOr<localization::Experiment2Result> a = localization::RunExperiment2(p, seed);
    if (!s.ok() || !a.ok()) {
      std::fprintf(stderr, "experiment failed for seed %d\n", seed);
      return 1;
    }
    after.insert(after.end(), s->along_track_after_marker_m.begin(),
                 s->along_track_after_marker_m.end());
    lateral.push_back(s->lateral_max_m);
    amcl_final.push_back(a->along_track_final_m);
  }
  std::printf(
      "{\"seeds\": %d, \"samcl_along_track_after_marker_m_p95\": %.4f, "
      "\"amcl_along_track_final_m_median\": %.4f, \"samcl_lateral_m_p95\": %.4f}\n",
      seeds, Percentile(after, 0.95), Percentile(amcl_final, 0.5), Percentile(lateral, 0.95));
  return 0;
}

}  // namespace
}  // namespace fleetnav::loc_bench

int main(int argc, char** argv) {
  constexpr const char* kUsage =
      "usage: fleetnav-loc-bench --json | --experiment samcl-vs-amcl [--seeds N] | --version\n"
      "  --json        particle filter speed (ns per particle and beam) as JSON\n"
      "  --experiment  samcl-vs-amcl: localization error with and without markers over seeds\n";
  std::string experiment;
  int seeds = 20;
  bool json = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--version") {
      std::printf("%s\n", std::string(fleetnav::Version()).c_str());
      return 0;
    }
    if (arg == "--help" || arg == "-h") {
      std::printf("%s", kUsage);
      return 0;
    }
    if (arg == "--json") {
      json = true;
    } else if (arg == "--experiment" && i + 1 < argc) {
      experiment = argv[++i];
    } else if (arg == "--seeds" && i + 1 < argc) {
      seeds = std::atoi(argv[++i]);
    } else {
      std::fprintf(stderr, "%s", kUsage);
      return 2;
    }
  }
  if (!experiment.empty()) {
    if (experiment != "samcl-vs-amcl" || seeds < 1) {
      std::fprintf(stderr, "unknown experiment '%s' or bad --seeds\n", experiment.c_str());
      return 2;
    }
    return fleetnav::loc_bench::RunExperiment(seeds);
  }
  if (!json) {
    std::fprintf(stderr, "%s", kUsage);
    return 2;
  }
  return fleetnav::loc_bench::RunSpeed();
}
