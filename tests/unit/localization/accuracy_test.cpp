// Statistical accuracy over ≥ 20 seeds on synthetic data from known trajectories in a known
// barn-like map (issue 5, "Accuracy"). Printed figures go into docs/localization.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "fleetnav/localization/amcl.hpp"
#include "fleetnav/localization/synthetic.hpp"

namespace fleetnav::localization {
namespace {

constexpr int kSeeds = 20;

double Percentile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  const size_t i = std::min(v.size() - 1, static_cast<size_t>(std::ceil(q * v.size())) - 1);
  return v[i];
}

TEST(AccuracyTest, Experiment2SamclBeatsAmclAlongTheFence) {
  std::vector<double> samcl_after, samcl_lateral, amcl_final, amcl_mid;
  int amcl_grows = 0;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    Experiment2Params p;
    p.use_samcl = true;
    const Experiment2Result s = *RunExperiment2(p, seed);
    ASSERT_EQ(s.calibrations, 2) << "seed " << seed;
    for (double e : s.along_track_after_marker_m) samcl_after.push_back(e);
    samcl_lateral.push_back(s.lateral_max_m);
    p.use_samcl = false;
    const Experiment2Result a = *RunExperiment2(p, seed);
    amcl_final.push_back(a.along_track_final_m);
    amcl_mid.push_back(a.along_track_mid_m);
    if (a.along_track_final_m > a.along_track_mid_m) ++amcl_grows;
  }
  std::printf(
      "experiment2: samcl after-marker p95 %.4f max %.4f m, samcl lateral p95 %.4f max %.4f m, "
      "amcl final median %.4f m, amcl mid median %.4f m, amcl grows in %d/%d\n",
      Percentile(samcl_after, 0.95), Percentile(samcl_after, 1.0), Percentile(samcl_lateral, 0.95),
      Percentile(samcl_lateral, 1.0), Percentile(amcl_final, 0.5), Percentile(amcl_mid, 0.5),
      amcl_grows, kSeeds);
  // SAMCL: along-track ≤ 2 cm right after each marker, lateral ≤ 5 cm throughout, every seed.
  EXPECT_LE(Percentile(samcl_after, 1.0), 0.02);
  EXPECT_LE(Percentile(samcl_lateral, 1.0), 0.05);
  // AMCL with the fake laser: the along-track error grows with distance.
  EXPECT_GE(amcl_grows, kSeeds * 9 / 10);
  EXPECT_GT(Percentile(amcl_final, 0.5), 0.1);
  EXPECT_GT(Percentile(amcl_final, 0.5), 5.0 * Percentile(samcl_after, 0.95));
}

// A straight drive east along y = 2.5 through the barn, 0.1 m odometry steps.
struct Drive {
  std::vector<Pose2> truth;
  std::vector<Pose2> odom;
};

Drive MakeDrive(Rng& rng, Pose2 start, double length_m, double scale_error) {
  Drive d;
  Pose2 truth = start;
  Pose2 odom;
  const int steps = static_cast<int>(length_m / 0.1);
  for (int i = 0; i <= steps; ++i) {
    d.truth.push_back(truth);
    d.odom.push_back(odom);
    const double turn = 0.02 * std::sin(i * 0.05);
    truth = truth * Pose2(0.1, 0.0, turn);
    odom = odom * Pose2(0.1 * (1.0 + scale_error), 0.0, turn + 0.002 * rng.Normal());
  }
  return d;
}

AmclParams LaserParams(uint64_t seed) {
  AmclParams p;
  p.seed = seed;
  p.motion.alpha1 = 0.05;
  p.motion.alpha2 = 0.01;
  p.motion.alpha3 = 0.01;
  p.motion.alpha4 = 0.01;
  p.likelihood_field.sigma_hit_m = 0.1;
  p.likelihood_field.beam_exponent = 0.3;
  p.update_min_distance_m = 0.05;
  return p;
}

TEST(AccuracyTest, LaserTrackingRmseAtThousandParticles) {
  const OccupancyGrid map = *SyntheticBarnMap(0.05);
  std::vector<double> rmse;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    Rng rng(seed);
    const Drive d = MakeDrive(rng, Pose2(-8.0, 2.5, 0.0), 12.0, 0.02);
    AmclParams p = LaserParams(seed);
    p.min_particles = p.max_particles = 1000;
    Amcl amcl = *Amcl::Create(p, map);
    ASSERT_TRUE(amcl.InitializePose(d.truth[0], {0.1, 0.1, 0.05}, d.odom[0], 0).ok());
    double sq = 0.0;
    int count = 0;
    for (size_t i = 0; i < d.truth.size(); ++i) {
      const RangeObservation scan = SimulateLaser(map, d.truth[i], 100, 12.0, 0.02, rng);
      ASSERT_TRUE(amcl.Update(d.odom[i], scan, static_cast<int64_t>(i) * 200'000'000).ok());
      if (i < 20) continue;  // the first 2 m converge from the 10 cm initial spread
      const Pose2 e = amcl.PoseInMap(d.odom[i]);
      sq += (e.translation() - d.truth[i].translation()).squaredNorm();
      ++count;
    }
    rmse.push_back(std::sqrt(sq / count));
    EXPECT_FALSE(amcl.health().lost);
  }
  std::printf("laser tracking 100 beams 1000 particles: RMSE median %.4f max %.4f m\n",
              Percentile(rmse, 0.5), Percentile(rmse, 1.0));
  EXPECT_LE(Percentile(rmse, 1.0), 0.05);
}

TEST(AccuracyTest, GlobalLocalizationConvergesWithinTenMetres) {
  const OccupancyGrid map = *SyntheticBarnMap(0.05);
  int converged = 0;
  std::vector<double> distance;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    Rng rng(1000 + seed);
    const Drive d = MakeDrive(rng, Pose2(-8.0, 2.5, 0.0), 14.0, 0.01);
    AmclParams p = LaserParams(seed);
    p.min_particles = 500;
    p.max_particles = 100000;
    p.update_min_distance_m = 0.2;
    p.likelihood_field.sigma_hit_m = 0.25;  // a wider basin for the first, coarse updates
    Amcl amcl = *Amcl::Create(p, map);
    ASSERT_TRUE(amcl.InitializeGlobal(d.odom[0], 0).ok());
    std::vector<double> error(d.truth.size());
    for (size_t i = 0; i < d.truth.size(); ++i) {
      const RangeObservation scan = SimulateLaser(map, d.truth[i], 60, 12.0, 0.02, rng);
      ASSERT_TRUE(amcl.Update(d.odom[i], scan, static_cast<int64_t>(i) * 200'000'000).ok());
      error[i] = (amcl.PoseInMap(d.odom[i]).translation() - d.truth[i].translation()).norm();
    }
    // Converged: from then on within 0.3 m until the end of the drive.
    size_t first = error.size();
    while (first > 0 && error[first - 1] < 0.3) --first;
    const double at_m = first * 0.1;
    distance.push_back(first < error.size() ? at_m : 1e9);
    if (first < error.size() && at_m <= 10.0) ++converged;
  }
  std::printf("global localization: %d/%d converged within 10 m, median %.2f m\n", converged,
              kSeeds, Percentile(distance, 0.5));
  EXPECT_GE(converged, (kSeeds * 95 + 99) / 100);
}

TEST(AccuracyTest, KidnappedRobotRecoversWithinThirtySeconds) {
  const OccupancyGrid map = *SyntheticBarnMap(0.05);
  int recovered = 0;
  std::vector<double> times;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    Rng rng(2000 + seed);
    // 4 m along y = 2.5, then teleported 5 m to (−2, −0.5) and on eastwards for 36 s, at
    // 0.25 m/s (0.1 m per 0.4 s step).
    Drive before = MakeDrive(rng, Pose2(-10.0, 2.5, 0.0), 4.0, 0.01);
    const Drive after = MakeDrive(rng, Pose2(-2.0, -0.5, 0.0), 9.0, 0.01);
    AmclParams p = LaserParams(seed);
    p.min_particles = 500;
    p.max_particles = 10000;
    p.likelihood_field.sigma_hit_m = 0.25;  // a wider basin for the injected particles
    Amcl amcl = *Amcl::Create(p, map);
    ASSERT_TRUE(amcl.InitializePose(before.truth[0], {0.05, 0.05, 0.02}, before.odom[0], 0).ok());
    int64_t stamp = 0;
    for (size_t i = 0; i < before.truth.size(); ++i, stamp += 400'000'000) {
      const RangeObservation scan = SimulateLaser(map, before.truth[i], 100, 12.0, 0.02, rng);
      ASSERT_TRUE(amcl.Update(before.odom[i], scan, stamp).ok());
    }
    // Odometry continues where it was: the kidnapping is invisible to it.
    const Pose2 odom_offset = before.odom.back();
    std::vector<double> error;
    for (size_t i = 0; i < after.truth.size(); ++i, stamp += 400'000'000) {
      const Pose2 odom = odom_offset * after.odom[i];
      const RangeObservation scan = SimulateLaser(map, after.truth[i], 100, 12.0, 0.02, rng);
      ASSERT_TRUE(amcl.Update(odom, scan, stamp).ok());
      error.push_back((amcl.PoseInMap(odom).translation() - after.truth[i].translation()).norm());
    }
    size_t first = error.size();
    while (first > 0 && error[first - 1] < 0.3) --first;
    const double seconds = first * 0.4;
    times.push_back(first < error.size() ? seconds : 1e9);
    if (first < error.size() && seconds <= 30.0) ++recovered;
  }
  std::printf("kidnapped robot: %d/%d recovered within 30 s, median %.1f s\n", recovered, kSeeds,
              Percentile(times, 0.5));
  EXPECT_GE(recovered, (kSeeds * 90 + 99) / 100);
}

}  // namespace
}  // namespace fleetnav::localization
