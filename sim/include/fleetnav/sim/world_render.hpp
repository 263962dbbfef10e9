#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "fleetnav/sim/world_description.hpp"

namespace fleetnav::sim {

/// One robot's path: ground truth (solid) or an estimate (dashed).
struct TrajectoryTrace {
  std::string robot_id;
  bool estimated = false;
  std::vector<Eigen::Vector2d> points_m;
};

struct RenderParams {
  double pixels_per_m = 40.0;
  double margin_m = 0.5;
};

/// Draws the world (floor, walls, fences, boxes, cylinders, stripes, markers, fault regions,
/// the robots' start footprints) and the trajectories, like the thesis figures (Lely Fig. 7.9,
/// 7.10). The format follows the file name: ".png" or ".svg" (cairo); InvalidArgument for any
/// other, Internal when cairo cannot write.
absl::Status RenderWorld(const WorldDescription& world,
                         const std::vector<TrajectoryTrace>& trajectories, const std::string& path,
                         RenderParams params = {});

/// Reads trajectories from CSV lines "robot_id,truth|estimate,x,y[,t_s]" (fleetnav-sim
/// --record-truth and fleetnav-agent --record write them; a header line starting with
/// "robot_id" and blank lines are skipped); InvalidArgument naming the line otherwise.
absl::StatusOr<std::vector<TrajectoryTrace>> LoadTrajectoriesCsv(const std::string& path);

}  // namespace fleetnav::sim
