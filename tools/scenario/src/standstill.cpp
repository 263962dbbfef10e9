#include "fleetnav/scenario/standstill.hpp"

#include <algorithm>
#include <cmath>

namespace fleetnav::scenario {

double LongestStandstillS(const std::map<std::string, std::vector<TruthSample>>& truth,
                          const std::vector<JobWindow>& jobs, double move_m) {
  std::vector<double> ticks;
  for (const auto& [robot, samples] : truth) {
    for (const TruthSample& s : samples) ticks.push_back(s.t_s);
  }
  std::sort(ticks.begin(), ticks.end());
  ticks.erase(std::unique(ticks.begin(), ticks.end()), ticks.end());
  struct Cursor {
    const std::vector<TruthSample>* samples;
    size_t next = 0;  ///< the first sample after the current tick
    double anchor_x_m = 0.0, anchor_y_m = 0.0;
    bool anchored = false;
  };
  std::vector<Cursor> robots;
  for (const auto& [robot, samples] : truth) robots.push_back({&samples});
  const auto work_to_do = [&](double t_s) {
    return std::any_of(jobs.begin(), jobs.end(), [&](const JobWindow& job) {
      return job.submitted_s <= t_s && (job.end_s < 0.0 || job.end_s > t_s);
    });
  };
  double longest_s = 0.0;
  double still_since_s = ticks.empty() ? 0.0 : ticks.front();
  for (double t_s : ticks) {
    bool moved = false;
    for (Cursor& robot : robots) {
      const std::vector<TruthSample>& samples = *robot.samples;
      while (robot.next < samples.size() && samples[robot.next].t_s <= t_s) ++robot.next;
      if (robot.next == 0) continue;  // not recorded yet
      const TruthSample& now = samples[robot.next - 1];
      if (!robot.anchored ||
          std::hypot(now.x_m - robot.anchor_x_m, now.y_m - robot.anchor_y_m) > move_m) {
        moved = moved || robot.anchored;
        robot.anchor_x_m = now.x_m;
        robot.anchor_y_m = now.y_m;
        robot.anchored = true;
      }
    }
    if (moved || !work_to_do(t_s)) {
      still_since_s = t_s;
    } else {
      longest_s = std::max(longest_s, t_s - still_since_s);
    }
  }
  return longest_s;
}

}  // namespace fleetnav::scenario
