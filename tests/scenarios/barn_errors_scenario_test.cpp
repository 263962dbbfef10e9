// The Lely drives the north feed alley of the barn with the thesis's error cases (Lely
// §7.1.2), driven by an in-process agent through the lockstep barrier: the left ultrasonic
// loses the fence exactly where case B removed it, the inductive sensor stays on stripe 1, and
// the run is drawn like the thesis's Fig. 7.10.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <thread>

#include "fleetnav/sim/lockstep.hpp"
#include "fleetnav/sim/world_render.hpp"

namespace fleetnav::sim {
namespace {

struct Sample {
  double sensor_x_m;  ///< the left ultrasonic's x (ground truth)
  bool echo;
  double range_m;
  bool on_stripe;
};

std::vector<Sample> DriveTheAlley(const std::string& world_file, TrajectoryTrace* trace) {
  absl::StatusOr<WorldDescription> world =
      LoadWorld(std::string(FLEETNAV_WORLDS_DIR) + "/" + world_file);
  EXPECT_TRUE(world.ok()) << world.status();
  SimulationParams params;
  params.seed = 3;
  absl::StatusOr<std::unique_ptr<Simulation>> sim = Simulation::Create(*world, params);
  EXPECT_TRUE(sim.ok());
  // On stripe 1 (y 4.7) with the left inductive sensor (y + 0.05) over it.
  EXPECT_TRUE((*sim)->AddRobot("lely1", "lely-vector", Pose2(-8.0, 4.65, 0.0)).ok());
  LockstepParams lockstep_params;
  lockstep_params.max_sim_time_s = 30.0;
  Lockstep lockstep(sim->get(), lockstep_params);
  std::unique_ptr<Attachment> attachment = *lockstep.Attach("lely1");
  std::thread loop([&] { lockstep.Run(); });

  std::vector<Sample> samples;
  trace->robot_id = "lely1";
  while (std::optional<SensorFrame> frame = attachment->WaitFrame()) {
    Pose2 pose;
    lockstep.Inspect([&](const Simulation& s) { pose = s.GroundTruth().robots[0].pose; });
    trace->points_m.push_back(pose.translation());
    Sample sample{pose.TransformPoint({1.57, 0.25}).x(), false, 0.0, false};
    for (const RangeReading& r : frame->ultrasonic) {
      if (r.name == "ultrasonic_left") {
        sample.echo = r.echo;
        sample.range_m = r.range_m;
      }
    }
    for (const InductiveSample& s : frame->inductive) {
      if (s.name == "inductive_left") sample.on_stripe = s.detected;
    }
    samples.push_back(sample);
    // A trivial agent: straight ahead at 0.5 m/s (the Lely tracks a straight line).
    ActuatorCommand command;
    command.tick = frame->tick;
    command.drive = Twist2{0.5, 0.0, 0.0};
    EXPECT_TRUE(attachment->Submit(command).ok());
  }
  loop.join();
  return samples;
}

TEST(BarnErrorsScenarioTest, FenceGapOfCaseBIsWhereTheUltrasonicLosesTheFence) {
  TrajectoryTrace intact_trace, errors_trace;
  const std::vector<Sample> intact = DriveTheAlley("barn.yaml", &intact_trace);
  const std::vector<Sample> errors = DriveTheAlley("barn_errors.yaml", &errors_trace);
  ASSERT_GT(intact.size(), 1000u);
  int checked = 0;
  for (size_t i = 0; i < errors.size(); ++i) {
    const Sample& s = errors[i];
    if (s.sensor_x_m < -6.0 || s.sensor_x_m > 8.0) continue;
    ++checked;
    // The robot stays on stripe 1 the whole way.
    EXPECT_TRUE(s.on_stripe) << "x " << s.sensor_x_m;
    // Case B: the fence is gone for x in [2, 4]; the cone (±5° at 0.9 m = ±8 cm) keeps a
    // margin at the ends.
    if (s.sensor_x_m > 2.1 && s.sensor_x_m < 3.9) {
      EXPECT_FALSE(s.echo) << "x " << s.sensor_x_m;
    }
    if ((s.sensor_x_m < 1.9 || s.sensor_x_m > 4.1) && s.echo) {
      EXPECT_NEAR(s.range_m, 0.95, 0.06) << "x " << s.sensor_x_m;
    }
  }
  EXPECT_GT(checked, 1000);
  int intact_echoes = 0, intact_in_gap = 0;
  for (const Sample& s : intact) {
    if (s.sensor_x_m > 2.1 && s.sensor_x_m < 3.9) {
      ++intact_in_gap;
      intact_echoes += s.echo ? 1 : 0;
    }
  }
  ASSERT_GT(intact_in_gap, 50);
  EXPECT_GT(intact_echoes, intact_in_gap * 9 / 10);

  absl::StatusOr<WorldDescription> world =
      LoadWorld(std::string(FLEETNAV_WORLDS_DIR) + "/barn_errors.yaml");
  ASSERT_TRUE(world.ok());
  const std::string picture = std::string(FLEETNAV_SCENARIO_OUT_DIR) + "/barn_errors_alley.png";
  ASSERT_TRUE(RenderWorld(*world, {errors_trace}, picture).ok());
  EXPECT_TRUE(std::filesystem::exists(picture));
}

}  // namespace
}  // namespace fleetnav::sim
