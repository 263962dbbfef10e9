#pragma once

#include <map>
#include <string>
#include <vector>

namespace fleetnav::scenario {

/// One robot's true pose at a sim time (the simulator's truth recording).
struct TruthSample {
  double t_s = 0.0;
  double x_m = 0.0;
  double y_m = 0.0;
  double yaw_rad = 0.0;
};

/// When a job was submitted and when it ended (sim seconds; end_s < 0: it never ended).
struct JobWindow {
  double submitted_s = 0.0;
  double end_s = -1.0;
};

/// The longest stretch of sim time in which the fleet stood still with work to do: no robot
/// got `move_m` from where it last moved to (so jitter and a turn in place are standing, a
/// slow creep is not), while some job had been submitted and had not ended. A gridlock shows as
/// a standstill as long as the rest of the run; a fleet that keeps flowing shows the longest
/// pause of everyone at once (a pick, a hold at a gate). Ticks are the samples' times, each
/// robot at its latest sample. Pure function.
double LongestStandstillS(const std::map<std::string, std::vector<TruthSample>>& truth,
                          const std::vector<JobWindow>& jobs, double move_m = 0.05);

}  // namespace fleetnav::scenario
