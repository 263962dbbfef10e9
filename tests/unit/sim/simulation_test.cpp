#include "fleetnav/sim/simulation.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "fleetnav/core/angles.hpp"
#include "sim_test_util.hpp"

namespace fleetnav::sim {
namespace {

using testing::EmptyWorld;
using testing::MakeSimulation;
using testing::TwistCommand;

// A varied command sequence: speed and turn rate change every few ticks.
ActuatorCommand CommandAt(int tick) {
  const double vx = 0.25 + 0.2 * std::sin(0.013 * tick);
  const double yaw_rate = (tick / 100) % 2 == 0 ? 0.2 : -0.15;
  ActuatorCommand command = TwistCommand(vx, yaw_rate);
  command.tick = static_cast<uint64_t>(tick);
  return command;
}

TEST(SimulationParamsTest, Validate) {
  EXPECT_TRUE(SimulationParams{}.Validate().ok());
  SimulationParams params;
  params.physics_step_s = 0.01;
  EXPECT_EQ(params.Validate().code(), absl::StatusCode::kInvalidArgument);
  params = {};
  params.physics_step_s = 0.0;
  EXPECT_EQ(params.Validate().code(), absl::StatusCode::kInvalidArgument);
  params = {};
  params.control_period_s = 0.021;  // 10.5 physics steps
  EXPECT_EQ(params.Validate().code(), absl::StatusCode::kInvalidArgument);
  params = {};
  params.control_period_s = 0.001;
  EXPECT_EQ(params.Validate().code(), absl::StatusCode::kInvalidArgument);
  params = {};
  params.control_period_s = 0.1;
  params.physics_step_s = 0.005;
  EXPECT_TRUE(params.Validate().ok());
  EXPECT_EQ(
      Simulation::Create(EmptyWorld(), SimulationParams{.physics_step_s = 0.02}).status().code(),
      absl::StatusCode::kInvalidArgument);
}

TEST(SimulationTest, ClockIsTicksTimesPeriod) {
  std::unique_ptr<Simulation> sim = MakeSimulation(1);
  ASSERT_TRUE(sim->AddRobot("lely1", "lely-vector", Pose2()).ok());
  EXPECT_EQ(sim->tick(), 0u);
  EXPECT_EQ(sim->now_ns(), 0);
  for (int i = 0; i < 7; ++i) sim->Advance();
  EXPECT_EQ(sim->tick(), 7u);
  EXPECT_EQ(sim->now_ns(), 140'000'000);
  absl::StatusOr<SensorFrame> frame = sim->Sense("lely1");
  ASSERT_TRUE(frame.ok());
  EXPECT_EQ(frame->tick, 7u);
  EXPECT_EQ(frame->stamp_ns, 140'000'000);
  EXPECT_DOUBLE_EQ(frame->control_period_s, 0.02);
  ASSERT_NE(frame->FindEncoder("left"), nullptr);
  ASSERT_NE(frame->FindEncoder("right"), nullptr);
  const GroundTruthSnapshot truth = sim->GroundTruth();
  EXPECT_EQ(truth.tick, 7u);
  EXPECT_EQ(truth.sim_time_ns, 140'000'000);
  EXPECT_EQ(truth.min_separation_m, std::numeric_limits<double>::infinity());
  EXPECT_TRUE(truth.contacts.empty());
}

TEST(SimulationTest, AddRobotErrors) {
  std::unique_ptr<Simulation> sim = MakeSimulation(1);
  ASSERT_TRUE(sim->AddRobot("lely1", "lely-vector", Pose2(0, 0, 0)).ok());
  EXPECT_EQ(sim->AddRobot("lely1", "lely-vector", Pose2(5, 5, 0)).code(),
            absl::StatusCode::kAlreadyExists);
  EXPECT_EQ(sim->AddRobot("x", "hovercraft", Pose2(5, 5, 0)).code(), absl::StatusCode::kNotFound);
  EXPECT_EQ(sim->AddRobot("", "lely-vector", Pose2(5, 5, 0)).code(),
            absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(sim->AddRobot("n", "lely-vector", Pose2(std::nan(""), 5, 0)).code(),
            absl::StatusCode::kInvalidArgument);
  // Nothing but the first robot was added.
  EXPECT_EQ(sim->robot_ids(), std::vector<std::string>{"lely1"});
  EXPECT_EQ(sim->GroundTruth().robots.size(), 1u);
  absl::StatusOr<RobotModel> model = sim->ModelOf("lely1");
  ASSERT_TRUE(model.ok());
  EXPECT_EQ(model->kind_name, "lely-vector");
  EXPECT_EQ(sim->ModelOf("m").status().code(), absl::StatusCode::kNotFound);
  EXPECT_EQ(sim->Sense("m").status().code(), absl::StatusCode::kNotFound);
}

// Two simulations with one seed and one command sequence, stepped interleaved in one process,
// end in bit-identical states: no hidden global state (ODE's own random generator) leaks.
TEST(SimulationDeterminismTest, SameSeedSameCommandsBitIdentical) {
  std::unique_ptr<Simulation> a = MakeSimulation(77);
  std::unique_ptr<Simulation> b = MakeSimulation(77);
  for (Simulation* sim : {a.get(), b.get()}) {
    ASSERT_TRUE(sim->AddRobot("lely1", "lely-vector", Pose2(0, 0, 0.3)).ok());
    ASSERT_TRUE(sim->AddRobot("lely2", "lely-vector", Pose2(5, 0, 0)).ok());
  }
  for (int tick = 0; tick < 500; ++tick) {
    for (Simulation* sim : {a.get(), b.get()}) {
      absl::StatusOr<SensorFrame> f1 = sim->Sense("lely1");
      ASSERT_TRUE(f1.ok());
      ASSERT_TRUE(sim->Command("lely1", CommandAt(tick)).ok());
      ASSERT_TRUE(sim->Command("lely2", CommandAt(tick + 50)).ok());
      sim->Advance();
    }
  }
  const GroundTruthSnapshot ta = a->GroundTruth();
  const GroundTruthSnapshot tb = b->GroundTruth();
  ASSERT_EQ(ta.robots.size(), 2u);
  ASSERT_EQ(tb.robots.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(ta.robots[i].pose.x_m(), tb.robots[i].pose.x_m()) << i;
    EXPECT_EQ(ta.robots[i].pose.y_m(), tb.robots[i].pose.y_m()) << i;
    EXPECT_EQ(ta.robots[i].pose.yaw_rad(), tb.robots[i].pose.yaw_rad()) << i;
    EXPECT_EQ(ta.robots[i].velocity.vx_mps, tb.robots[i].velocity.vx_mps) << i;
  }
  // The robots really moved.
  EXPECT_GT(ta.robots[0].pose.translation().norm(), 1.0);
  absl::StatusOr<SensorFrame> fa = a->Sense("lely1");
  absl::StatusOr<SensorFrame> fb = b->Sense("lely1");
  ASSERT_TRUE(fa.ok() && fb.ok());
  EXPECT_EQ(fa->imu.gyro_z_radps, fb->imu.gyro_z_radps);
  for (const char* wheel : {"left", "right"}) {
    ASSERT_NE(fa->FindEncoder(wheel), nullptr);
    ASSERT_NE(fb->FindEncoder(wheel), nullptr);
    EXPECT_EQ(fa->FindEncoder(wheel)->ticks, fb->FindEncoder(wheel)->ticks) << wheel;
  }
}

std::vector<double> GyroSamples(Simulation& sim, const std::string& robot_id, int count) {
  std::vector<double> samples;
  for (int i = 0; i < count; ++i) {
    absl::StatusOr<SensorFrame> frame = sim.Sense(robot_id);
    EXPECT_TRUE(frame.ok());
    samples.push_back(frame.ok() ? frame->imu.gyro_z_radps : 0.0);
    sim.Advance();
  }
  return samples;
}

TEST(SimulationDeterminismTest, DifferentSeedDifferentGyroNoise) {
  std::unique_ptr<Simulation> a = MakeSimulation(1);
  std::unique_ptr<Simulation> b = MakeSimulation(2);
  ASSERT_TRUE(a->AddRobot("lely1", "lely-vector", Pose2()).ok());
  ASSERT_TRUE(b->AddRobot("lely1", "lely-vector", Pose2()).ok());
  const std::vector<double> ga = GyroSamples(*a, "lely1", 50);
  const std::vector<double> gb = GyroSamples(*b, "lely1", 50);
  int equal = 0;
  for (size_t i = 0; i < ga.size(); ++i) equal += ga[i] == gb[i] ? 1 : 0;
  EXPECT_EQ(equal, 0);
}

// The gyro noise of a robot (reading minus the true yaw rate) is its own stream: a second
// robot in the world leaves the first one's noise sequence unchanged.
TEST(SimulationDeterminismTest, SecondRobotLeavesTheFirstRobotsNoise) {
  std::unique_ptr<Simulation> alone = MakeSimulation(9);
  std::unique_ptr<Simulation> pair = MakeSimulation(9);
  ASSERT_TRUE(alone->AddRobot("lely1", "lely-vector", Pose2(0, 0, 0)).ok());
  ASSERT_TRUE(pair->AddRobot("lely2", "lely-vector", Pose2(-6, 4, 1.0)).ok());  // added first
  ASSERT_TRUE(pair->AddRobot("lely1", "lely-vector", Pose2(0, 0, 0)).ok());
  ASSERT_TRUE(pair->Command("lely2", TwistCommand(0.3, 0.1)).ok());
  double noise_power = 0.0;
  for (int i = 0; i < 200; ++i) {
    const double true_alone = alone->GroundTruth().robots.at(0).velocity.yaw_rate_radps;
    const double true_pair = pair->GroundTruth().robots.at(1).velocity.yaw_rate_radps;
    absl::StatusOr<SensorFrame> fa = alone->Sense("lely1");
    absl::StatusOr<SensorFrame> fp = pair->Sense("lely1");
    ASSERT_TRUE(fa.ok() && fp.ok());
    // Noise ≈ 2e-3 rad/s; equal to well below a part in a million.
    ASSERT_NEAR(fa->imu.gyro_z_radps - true_alone, fp->imu.gyro_z_radps - true_pair, 1e-12)
        << "tick " << i;
    noise_power += std::pow(fa->imu.gyro_z_radps - true_alone, 2);
    alone->Advance();
    pair->Advance();
  }
  EXPECT_GT(noise_power / 200, 1e-7);  // the noise is there
}

// Driving into a wall: the chassis contact is reported, the robot stops at the wall instead of
// passing through it, and it stays upright while its motors keep pushing.
TEST(SimulationTest, WallStopsTheRobotAndIsReported) {
  WorldDescription world = EmptyWorld();
  world.boxes.push_back({"wall", Eigen::Vector2d(3.0, 0.0), Eigen::Vector2d(0.2, 6.0), 0.0, 2.5});
  absl::StatusOr<std::unique_ptr<Simulation>> sim = Simulation::Create(world, SimulationParams{});
  ASSERT_TRUE(sim.ok()) << sim.status();
  ASSERT_TRUE((*sim)->AddRobot("lely1", "lely-vector", Pose2(0, 0, 0)).ok());
  absl::StatusOr<RobotModel> model = (*sim)->ModelOf("lely1");
  ASSERT_TRUE(model.ok());
  double front_m = 0.0;
  for (const Eigen::Vector2d& p : model->footprint_m) front_m = std::max(front_m, p.x());
  const double stop_x = 2.9 - front_m;  // base_link when the front touches the wall
  ASSERT_TRUE((*sim)->Command("lely1", TwistCommand(0.3, 0.0)).ok());
  double min_up_z = 1.0;
  for (int i = 0; i < 600; ++i) {  // 12 s: 3.6 m if nothing stopped it
    (*sim)->Advance();
    const RobotTruth truth = (*sim)->GroundTruth().robots.at(0);
    ASSERT_TRUE(truth.pose.IsFinite());
    ASSERT_LT(truth.pose.x_m(), stop_x + 0.02) << "tick " << i;
    min_up_z = std::min(min_up_z, truth.up_z);
  }
  const GroundTruthSnapshot truth = (*sim)->GroundTruth();
  EXPECT_GT(truth.robots.at(0).pose.x_m(), stop_x - 0.05);
  EXPECT_GT(min_up_z, 0.95);
  ASSERT_FALSE(truth.contacts.empty());
  EXPECT_EQ(truth.contacts.front().robot_id, "lely1");
  EXPECT_EQ(truth.contacts.front().other, "static");
  EXPECT_GT(truth.contacts.front().sim_time_ns, 4'000'000'000);
  // Thousands of touching physics steps, but one contact episode, with the world.
  EXPECT_GT(truth.contacts.size(), 100u);
  EXPECT_EQ(truth.robots.at(0).collisions_world, 1);
  EXPECT_EQ(truth.robots.at(0).collisions_robots, 0);
  EXPECT_EQ(truth.robots.at(0).collisions(), 1);
}

// Backing off and driving in again is a second episode; Reset clears the count.
TEST(SimulationTest, EachRunIntoTheWallIsOneEpisode) {
  WorldDescription world = EmptyWorld();
  world.boxes.push_back({"wall", Eigen::Vector2d(3.0, 0.0), Eigen::Vector2d(0.2, 6.0), 0.0, 2.5});
  absl::StatusOr<std::unique_ptr<Simulation>> sim = Simulation::Create(world, SimulationParams{});
  ASSERT_TRUE(sim.ok()) << sim.status();
  ASSERT_TRUE((*sim)->AddRobot("lely1", "lely-vector", Pose2(0, 0, 0)).ok());
  std::vector<int> episodes;
  for (int run = 0; run < 2; ++run) {
    ASSERT_TRUE((*sim)->Command("lely1", TwistCommand(0.3, 0.0)).ok());
    for (int i = 0; i < 400; ++i) (*sim)->Advance();
    // Turn away from the wall (the Lely never reverses), drive off, and turn back to face it.
    for (const Twist2& leg :
         {Twist2{0.0, 0.0, 0.4}, Twist2{0.3, 0.0, 0.0}, Twist2{0.0, 0.0, 0.4}}) {
      ASSERT_TRUE((*sim)->Command("lely1", TwistCommand(leg.vx_mps, leg.yaw_rate_radps)).ok());
      for (int i = 0; i < (leg.vx_mps > 0 ? 250 : 393); ++i) (*sim)->Advance();
    }
    ASSERT_TRUE((*sim)->Command("lely1", TwistCommand(0.0, 0.0)).ok());
    for (int i = 0; i < 50; ++i) (*sim)->Advance();
    episodes.push_back((*sim)->GroundTruth().robots.at(0).collisions_world);
    std::printf("[ figures  ] run %d: %d contact episode(s) with the world so far\n", run,
                episodes.back());
  }
  // The first run touches the wall (and may scrape it once more turning away); the second,
  // which again drives into it, adds at least one episode; thousands of steps are not counted.
  EXPECT_GE(episodes[0], 1);
  EXPECT_LE(episodes[0], 2);
  EXPECT_GT(episodes[1], episodes[0]);
  EXPECT_LE(episodes[1], 4);
  EXPECT_EQ((*sim)->GroundTruth().robots.at(0).collisions_robots, 0);
  (*sim)->Reset(2);
  EXPECT_EQ((*sim)->GroundTruth().robots.at(0).collisions(), 0);
}

TEST(SimulationTest, TwoRobotsReportFootprintSeparation) {
  // In line, 10 m apart: the gap is 10 m less one 2.27 m body length.
  std::unique_ptr<Simulation> sim = MakeSimulation(1);
  ASSERT_TRUE(sim->AddRobot("a", "lely-vector", Pose2(0, 0, 0)).ok());
  ASSERT_TRUE(sim->AddRobot("b", "lely-vector", Pose2(10, 0, 0)).ok());
  sim->Advance();
  EXPECT_NEAR(sim->GroundTruth().min_separation_m, 10.0 - 2.27, 0.02);
  EXPECT_EQ(sim->robot_ids(), (std::vector<std::string>{"a", "b"}));

  // Side by side on lanes 3 m apart: 3 m less one 1.60 m body width (circumscribed circles
  // would call it 0.24 m).
  std::unique_ptr<Simulation> lanes = MakeSimulation(1);
  ASSERT_TRUE(lanes->AddRobot("a", "lely-vector", Pose2(0, 0, 0)).ok());
  ASSERT_TRUE(lanes->AddRobot("b", "lely-vector", Pose2(0.7, 3.0, 0)).ok());
  lanes->Advance();
  EXPECT_NEAR(lanes->GroundTruth().min_separation_m, 3.0 - 1.60, 0.02);
  EXPECT_EQ(lanes->GroundTruth().robots.at(0).collisions_robots, 0);
}

}  // namespace
}  // namespace fleetnav::sim

namespace fleetnav::sim {
namespace {

// The inductive pair over a 5 cm stripe: each sensor reads where the stripe crosses its lateral
// line (the thesis's sensor), so a robot centred on the stripe still sees it; a marker crossed
// at right angles gives `detected` but no lateral reading.
TEST(SimulationTest, InductiveSensorsReadTheStripesLateralOffset) {
  WorldDescription world = EmptyWorld();
  world.stripes.push_back(
      {1, {Eigen::Vector2d(-5.0, 0.0), Eigen::Vector2d(5.0, 0.0)}, 0.05, false});
  SimulationParams params;
  params.exteroceptive.inductive_noise_m = 0.0;
  absl::StatusOr<std::unique_ptr<Simulation>> sim = Simulation::Create(world, params);
  ASSERT_TRUE(sim.ok()) << sim.status();
  ASSERT_TRUE((*sim)->AddRobot("lely1", "lely-vector", Pose2(0.0, 0.08, 0.0)).ok());
  absl::StatusOr<SensorFrame> frame = (*sim)->Sense("lely1");
  ASSERT_TRUE(frame.ok());
  ASSERT_EQ(frame->inductive.size(), 2u);
  for (const InductiveSample& s : frame->inductive) {
    ASSERT_TRUE(s.lateral_offset_m.has_value()) << s.name;
    // Sensors at y = 0.08 ± 0.05: the stripe is 0.13 m and 0.03 m to their right.
    EXPECT_NEAR(*s.lateral_offset_m, s.name == "inductive_left" ? -0.13 : -0.03, 1e-9) << s.name;
    EXPECT_FALSE(s.detected) << s.name;  // neither sensor point is over the 5 cm of metal
  }
  // 0.3 m to the side: out of the sensors' ±0.15 m range.
  ASSERT_TRUE((*sim)->AddRobot("lely2", "lely-vector", Pose2(0.0, 3.3, 0.0)).ok());
  frame = (*sim)->Sense("lely2");
  ASSERT_TRUE(frame.ok());
  for (const InductiveSample& s : frame->inductive) EXPECT_FALSE(s.lateral_offset_m) << s.name;
}

TEST(SimulationTest, BatteryDrainsWithDistanceAndChargesOnTheCharger) {
  WorldDescription world = EmptyWorld();
  world.cylinders.push_back({"charging_pole", Eigen::Vector2d(3.0, 0.0), 0.15, 1.5});
  SimulationParams params;
  params.battery.initial_fraction = 0.5;
  params.battery.drain_per_m = 0.01;
  params.battery.drain_per_s = 0.0;
  params.battery.charge_per_s = 0.01;
  absl::StatusOr<std::unique_ptr<Simulation>> sim = Simulation::Create(world, params);
  ASSERT_TRUE(sim.ok()) << sim.status();
  ASSERT_TRUE((*sim)->AddRobot("lely1", "lely-vector", Pose2(0.0, 0.0, 0.0)).ok());
  EXPECT_NEAR(*(*sim)->Sense("lely1")->battery_fraction, 0.5, 1e-12);
  ASSERT_TRUE((*sim)->Command("lely1", TwistCommand(0.1, 0.0)).ok());
  double last = 0.5;
  bool charged = false;
  for (int i = 0; i < 1500; ++i) {
    (*sim)->Advance();
    absl::StatusOr<SensorFrame> frame = (*sim)->Sense("lely1");
    ASSERT_TRUE(frame.ok());
    if (frame->charger_contact) {
      ASSERT_TRUE((*sim)->Command("lely1", TwistCommand(0.0, 0.0)).ok());
      charged |= *frame->battery_fraction > last + 1e-9;
    } else if (!charged) {
      ASSERT_LE(*frame->battery_fraction, last + 1e-12) << "tick " << i;
    }
    last = *frame->battery_fraction;
  }
  // Driven ~0.2 m before the contact closed (front at 1.395 m, pole face at 2.85 m): 0.2 % gone,
  // then charged at 1 %/s for the rest of the 30 s.
  EXPECT_TRUE(charged);
  EXPECT_GT(last, 0.6);
}

}  // namespace
}  // namespace fleetnav::sim
