// Google Benchmark cases for the localization hot paths: likelihood-field weighting, the full
// AMCL update and systematic resampling. Figures go into docs/localization.md. The 40 m range
// makes every beam an echo in the 26 m barn (no-echo beams check their whole free path).
#include <benchmark/benchmark.h>

#include <vector>

#include "fleetnav/localization/amcl.hpp"
#include "fleetnav/localization/synthetic.hpp"

namespace fleetnav::localization {
namespace {

const OccupancyGrid& Map() {
  static const OccupancyGrid* map = new OccupancyGrid(*SyntheticBarnMap(0.05));
  return *map;
}

void BM_LikelihoodFieldWeigh(benchmark::State& state) {
  const size_t n = static_cast<size_t>(state.range(0));
  const int beams = static_cast<int>(state.range(1));
  const LikelihoodField field = *LikelihoodField::Create(Map(), LikelihoodFieldParams{});
  Rng rng(1);
  const Pose2 truth(-4.0, 2.5, 0.3);
  const RangeObservation scan = SimulateLaser(Map(), truth, beams, 40.0, 0.02, rng);
  std::vector<float> x(n), y(n), yaw(n), ll(n, 0.0f);
  for (size_t i = 0; i < n; ++i) {
    x[i] = static_cast<float>(truth.x_m() + 0.1 * rng.Normal());
    y[i] = static_cast<float>(truth.y_m() + 0.1 * rng.Normal());
    yaw[i] = static_cast<float>(truth.yaw_rad() + 0.05 * rng.Normal());
  }
  for (auto _ : state) {
    field.Accumulate(scan, x.data(), y.data(), yaw.data(), n, ll.data());
    benchmark::DoNotOptimize(ll.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(n) * beams);
}
BENCHMARK(BM_LikelihoodFieldWeigh)->Args({2000, 60})->Args({10000, 100})->Args({100000, 100});

void BM_AmclUpdate(benchmark::State& state) {
  AmclParams params;
  params.min_particles = params.max_particles = static_cast<size_t>(state.range(0));
  params.update_min_distance_m = 0.0;
  params.update_min_angle_rad = 0.0;
  params.resample_neff_ratio = 1.0;
  Amcl amcl = *Amcl::Create(params, Map());
  Pose2 truth(-8.0, 2.5, 0.0);
  Pose2 odom;
  (void)amcl.InitializePose(truth, {0.1, 0.1, 0.05}, odom, 0);
  Rng rng(2);
  const RangeObservation scan =
      SimulateLaser(Map(), truth, static_cast<int>(state.range(1)), 40.0, 0.02, rng);
  int64_t stamp = 0;
  for (auto _ : state) {
    // Small back-and-forth motion keeps the robot where the scan was taken.
    odom = odom * Pose2((stamp / 100'000'000) % 2 == 0 ? 0.01 : -0.01, 0.0, 0.0);
    stamp += 100'000'000;
    benchmark::DoNotOptimize(amcl.Update(odom, scan, stamp));
  }
}
BENCHMARK(BM_AmclUpdate)
    ->Args({2000, 60})
    ->Args({10000, 60})
    ->Args({10000, 100})
    ->Args({100000, 100})
    ->Unit(benchmark::kMillisecond);

void BM_SystematicResample(benchmark::State& state) {
  const size_t n = static_cast<size_t>(state.range(0));
  Rng rng(3);
  std::vector<double> w(n);
  for (double& v : w) v = rng.Uniform();
  std::vector<uint32_t> idx;
  for (auto _ : state) {
    SystematicResample(w, n, rng, idx);
    benchmark::DoNotOptimize(idx.data());
  }
  state.SetComplexityN(static_cast<int64_t>(n));
}
BENCHMARK(BM_SystematicResample)->RangeMultiplier(10)->Range(1000, 1000000)->Complexity();

}  // namespace
}  // namespace fleetnav::localization

BENCHMARK_MAIN();
