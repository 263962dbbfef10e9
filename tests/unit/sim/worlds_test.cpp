// Every shipped world loads, simulates its robots, and yields its map and marker set.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "fleetnav/sim/simulation.hpp"
#include "fleetnav/sim/world_rasterizer.hpp"
#include "fleetnav/sim/world_render.hpp"

namespace fleetnav::sim {
namespace {

WorldDescription LoadShipped(const std::string& name) {
  absl::StatusOr<WorldDescription> world = LoadWorld(std::string(FLEETNAV_WORLDS_DIR) + "/" + name);
  EXPECT_TRUE(world.ok()) << world.status();
  return world.ok() ? *world : WorldDescription{};
}

class ShippedWorldTest : public ::testing::TestWithParam<const char*> {};

TEST_P(ShippedWorldTest, LoadsRasterizesAndRunsItsRobots) {
  const WorldDescription world = LoadShipped(GetParam());
  ASSERT_FALSE(world.robots.empty());
  absl::StatusOr<OccupancyGrid> grid = RasterizeWorld(world, 0.05);
  ASSERT_TRUE(grid.ok()) << grid.status();
  int occupied = 0;
  for (int8_t cell : grid->cells()) occupied += cell > 50 ? 1 : 0;
  EXPECT_GT(occupied, 100);
  absl::StatusOr<std::unique_ptr<Simulation>> sim = Simulation::Create(world, SimulationParams{});
  ASSERT_TRUE(sim.ok()) << sim.status();
  for (const RobotSpawn& spawn : world.robots) {
    ASSERT_TRUE((*sim)->AddRobot(spawn.robot_id, spawn.kind_name, spawn.pose).ok());
  }
  for (int i = 0; i < 50; ++i) {
    for (const RobotSpawn& spawn : world.robots) {
      absl::StatusOr<SensorFrame> frame = (*sim)->Sense(spawn.robot_id);
      ASSERT_TRUE(frame.ok());
      EXPECT_FALSE(frame->bumper) << spawn.robot_id << " starts touching something";
      ActuatorCommand command;
      command.drive = Twist2{0.2, 0.0, 0.0};
      ASSERT_TRUE((*sim)->Command(spawn.robot_id, command).ok());
    }
    (*sim)->Advance();
  }
  EXPECT_TRUE((*sim)->GroundTruth().contacts.empty());
  const std::filesystem::path dir = std::filesystem::temp_directory_path();
  for (const char* ext : {".png", ".svg"}) {
    // Named after the file, not the world: barn.yaml and barn_errors.yaml are one site, and
    // the two test instances run in parallel.
    const std::string path = (dir / (std::string("fleetnav_render_") +
                                     std::filesystem::path(GetParam()).stem().string() + "_" +
                                     std::to_string(getpid()) + ext))
                                 .string();
    std::vector<TrajectoryTrace> traces = {
        {world.robots[0].robot_id,
         false,
         {world.robots[0].pose.translation(),
          world.robots[0].pose.translation() + Eigen::Vector2d(1, 1)}},
        {world.robots[0].robot_id,
         true,
         {world.robots[0].pose.translation(),
          world.robots[0].pose.translation() + Eigen::Vector2d(1, 1.1)}}};
    ASSERT_TRUE(RenderWorld(world, traces, path, RenderParams{10.0, 0.5}).ok());
    EXPECT_GT(std::filesystem::file_size(path), 500u);
    std::ifstream in(path, std::ios::binary);
    std::string head(4, '\0');
    in.read(head.data(), 4);
    EXPECT_EQ(head, std::string(ext) == ".png" ? std::string("\x89PNG") : std::string("<?xm"));
    std::filesystem::remove(path);
  }
}

INSTANTIATE_TEST_SUITE_P(Worlds, ShippedWorldTest,
                         ::testing::Values("barn.yaml", "barn_errors.yaml", "supermarket.yaml",
                                           "delivery_yard.yaml"));

TEST(ShippedWorldsTest, SupermarketTrolleysStandOnFourLegsOnTheExportedMap) {
  const WorldDescription world = LoadShipped("supermarket.yaml");
  ASSERT_EQ(world.trolleys.size(), 4u);
  const OccupancyGrid map = RasterizeWorld(world, 0.02).value();
  for (const Trolley& trolley : world.trolleys) {
    for (const Eigen::Vector2d& leg : trolley.LegsInTrolley()) {
      const Eigen::Vector2d at = trolley.pose().TransformPoint(leg);
      EXPECT_EQ(map.StateAtWorld(at), CellState::kOccupied) << trolley.id << " " << at.transpose();
    }
    // Under the basket the platform drives: free.
    EXPECT_EQ(map.StateAtWorld(trolley.center_m), CellState::kFree) << trolley.id;
  }
}

TEST(ShippedWorldsTest, DeliveryYardHasBoxesWithNearEqualGaps) {
  const WorldDescription world = LoadShipped("delivery_yard.yaml");
  std::vector<double> xs;
  for (const BoxObstacle& box : world.boxes) {
    if (box.kind == "parcel" && std::abs(box.center_m.y() + 4.0) < 1e-9)
      xs.push_back(box.center_m.x());
  }
  ASSERT_EQ(xs.size(), 5u);
  for (size_t i = 0; i + 1 < xs.size(); ++i) {
    const double gap = xs[i + 1] - xs[i] - 0.6;
    EXPECT_GE(gap, 0.99);
    EXPECT_LE(gap, 1.11);
  }
}

TEST(RenderTest, RejectsUnknownFormatsAndBadCsv) {
  const WorldDescription world = LoadShipped("barn.yaml");
  EXPECT_EQ(RenderWorld(world, {}, "/tmp/x.jpg").code(), absl::StatusCode::kInvalidArgument);
  const std::string csv = (std::filesystem::temp_directory_path() / "fleetnav_traj.csv").string();
  {
    std::ofstream out(csv);
    out << "robot_id,kind,x,y\nlely1,truth,0,0\nlely1,truth,1,0\nlely1,estimate,0,0.1\n";
  }
  absl::StatusOr<std::vector<TrajectoryTrace>> traces = LoadTrajectoriesCsv(csv);
  ASSERT_TRUE(traces.ok()) << traces.status();
  ASSERT_EQ(traces->size(), 2u);
  EXPECT_EQ((*traces)[0].points_m.size(), 2u);
  EXPECT_TRUE((*traces)[1].estimated);
  {
    std::ofstream out(csv);
    out << "lely1,guess,0,0\n";
  }
  EXPECT_EQ(LoadTrajectoriesCsv(csv).status().code(), absl::StatusCode::kInvalidArgument);
  std::filesystem::remove(csv);
}

}  // namespace
}  // namespace fleetnav::sim
