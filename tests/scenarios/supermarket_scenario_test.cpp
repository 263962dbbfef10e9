// The supermarket world of the KUKA thesis (ch. 15) as the simulator builds it: the platform's
// laser sees all four cylinder legs of the trolley ahead, and the platform's body fits between
// the legs, so a robot driven straight under the trolley's centre touches nothing. These check
// the world and the sensor model with commanded motion; docking in closed loop (trolley
// recognition, approach, latch) belongs to the store-robot work and is not tested here.
#include <gtest/gtest.h>

#include <cmath>

#include "fleetnav/sim/simulation.hpp"

namespace fleetnav::sim {
namespace {

std::unique_ptr<Simulation> Supermarket(const Pose2& omni_pose) {
  absl::StatusOr<WorldDescription> world =
      LoadWorld(std::string(FLEETNAV_WORLDS_DIR) + "/supermarket.yaml");
  EXPECT_TRUE(world.ok()) << world.status();
  absl::StatusOr<std::unique_ptr<Simulation>> sim = Simulation::Create(*world, SimulationParams{});
  EXPECT_TRUE(sim.ok());
  EXPECT_TRUE((*sim)->AddRobot("omni1", "mecanum-platform", omni_pose).ok());
  return std::move(*sim);
}

TEST(SupermarketScenarioTest, LaserSeesTheFourTrolleyLegs) {
  // The trolley at (-2, -1.8), 1.0 x 0.7 m, legs of radius 2 cm at its corners.
  const Pose2 omni(-5.0, -1.8, 0.0);
  std::unique_ptr<Simulation> sim = Supermarket(omni);
  absl::StatusOr<SensorFrame> frame = sim->Sense("omni1");
  ASSERT_TRUE(frame.ok());
  ASSERT_EQ(frame->lasers.size(), 1u);
  const LaserScanSample& scan = frame->lasers[0];
  const Pose2 laser = omni * Pose2(0.35, 0.0, 0.0);
  const double hx = 0.5 - 0.02, hy = 0.35 - 0.02;
  for (const Eigen::Vector2d& leg :
       {Eigen::Vector2d(-2 - hx, -1.8 - hy), Eigen::Vector2d(-2 - hx, -1.8 + hy),
        Eigen::Vector2d(-2 + hx, -1.8 - hy), Eigen::Vector2d(-2 + hx, -1.8 + hy)}) {
    // Some beam ends on this leg's surface.
    int hits = 0;
    for (size_t i = 0; i < scan.ranges_m.size(); ++i) {
      const double angle =
          laser.yaw_rad() + scan.angle_min_rad + static_cast<double>(i) * scan.angle_increment_rad;
      const Eigen::Vector2d end =
          laser.translation() +
          scan.ranges_m[i] * Eigen::Vector2d(std::cos(angle), std::sin(angle));
      if (std::abs((end - leg).norm() - 0.02) < 0.04) ++hits;
    }
    EXPECT_GE(hits, 1) << "leg at " << leg.transpose();
  }
}

}  // namespace
}  // namespace fleetnav::sim
