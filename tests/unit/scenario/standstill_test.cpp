#include "fleetnav/scenario/standstill.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

namespace fleetnav::scenario {
namespace {

/// A robot sampled at 10 Hz from 0 to `end_s`, at x(t).
template <typename Path>
std::vector<TruthSample> Samples(double end_s, Path x_of_t) {
  std::vector<TruthSample> out;
  for (int i = 0; i <= static_cast<int>(end_s * 10.0 + 0.5); ++i) {
    const double t_s = i * 0.1;
    out.push_back({t_s, x_of_t(t_s), 0.0});
  }
  return out;
}

TEST(StandstillTest, AFleetThatStopsWithAJobUnfinishedStandsStillUntilTheEnd) {
  // a drives 1 m/s until 30 s, then stands; b never moves; the job never ends.
  const std::map<std::string, std::vector<TruthSample>> truth = {
      {"a", Samples(100.0, [](double t) { return std::min(t, 30.0); })},
      {"b", Samples(100.0, [](double) { return 5.0; })}};
  EXPECT_NEAR(LongestStandstillS(truth, {{0.0, -1.0}}), 70.0, 0.11);
}

TEST(StandstillTest, StandingAfterEveryJobHasEndedOrBeforeAnyIsSubmittedIsNoStandstill) {
  // a drives from 20 s to 40 s; the one job is submitted at 20 s and ends at 40 s.
  const std::map<std::string, std::vector<TruthSample>> truth = {
      {"a", Samples(100.0, [](double t) { return std::clamp(t - 20.0, 0.0, 20.0); })}};
  EXPECT_LT(LongestStandstillS(truth, {{20.0, 40.0}}), 0.2);
}

TEST(StandstillTest, OneRobotMovingIsEnoughAndJitterIsNotMoving) {
  // a jitters by 1 cm all along; b drives from 10 s to 20 s and from 50 s to 60 s.
  const std::map<std::string, std::vector<TruthSample>> truth = {
      {"a", Samples(60.0, [](double t) { return 0.01 * std::sin(7.0 * t); })},
      {"b", Samples(60.0, [](double t) {
         return std::clamp(t - 10.0, 0.0, 10.0) + std::clamp(t - 50.0, 0.0, 10.0);
       })}};
  // Still from 20 s to 50 s (a's jitter does not count), then b moves again.
  EXPECT_NEAR(LongestStandstillS(truth, {{0.0, 60.0}}), 30.0, 0.11);
}

TEST(StandstillTest, ASlowCreepIsMoving) {
  // 2 cm/s: under 5 cm per sample, yet 5 cm every 2.5 s.
  const std::map<std::string, std::vector<TruthSample>> truth = {
      {"a", Samples(60.0, [](double t) { return 0.02 * t; })}};
  EXPECT_LT(LongestStandstillS(truth, {{0.0, -1.0}}), 2.7);
}

}  // namespace
}  // namespace fleetnav::scenario
