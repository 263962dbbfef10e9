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

/// How RenderWorld draws: its scale, its margin and which annotations it adds.
struct RenderParams {
  double pixels_per_m = 40.0;  ///< picture pixels (SVG points) per metre, in (0, 1000]
  double margin_m = 0.5;       ///< border around the world's extent
  bool legend = true;          ///< robot ids with their colours and the line styles
  bool path_labels = true;     ///< each robot's id at the start and at the end of its path
  bool scale_bar = true;       ///< a 1-2-5 m bar of about 20 % of the map's width
  double font_size_px = 11.0;  ///< of the path labels (the legend's is 1 px larger), in [4, 100]
};

/// Draws the world (floor, walls, fences, boxes, cylinders, stripes, markers, fault regions,
/// the robots' start footprints) and the trajectories, like the thesis figures (Lely Fig. 7.9,
/// 7.10). Every robot has its own colour (RobotColors in render_style.hpp, in the order of
/// world.robots, then of robots only the trajectories name), for its start footprint and both
/// its paths (truth solid, estimate dashed); a path starts at a dot and ends at an arrowhead,
/// both labelled with the robot's id. The legend goes in a corner of the map that it leaves
/// every path and label free in, or else right of the map (the picture then is wider than the
/// map); the scale bar in a bottom corner of the map. The format follows the file name: ".png"
/// or ".svg" (cairo); InvalidArgument for any other or for params out of range, Internal when
/// cairo cannot write.
absl::Status RenderWorld(const WorldDescription& world,
                         const std::vector<TrajectoryTrace>& trajectories, const std::string& path,
                         RenderParams params = {});

/// Reads trajectories from CSV lines "robot_id,truth|estimate,x,y[,t_s]" (fleetnav-sim
/// --record-truth and fleetnav-agent --record write them; a header line starting with
/// "robot_id" and blank lines are skipped); InvalidArgument naming the line otherwise.
absl::StatusOr<std::vector<TrajectoryTrace>> LoadTrajectoriesCsv(const std::string& path);

}  // namespace fleetnav::sim
