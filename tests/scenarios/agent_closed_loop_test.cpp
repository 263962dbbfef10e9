// fleetnav-sim and fleetnav-agent as processes, in closed loop, judged by the simulator's
// ground truth (pose, contact episodes), never by the agent's belief about itself. The world
// is written here: a hall with a feeding fence along y = 2 m, two calibration markers and a
// robot (lely1) near the fence; a floor stripe along y = -5 m (out of lely1's ultrasonic range)
// leading to a charger stripe and a charging pole, with a second robot (lely2) on it. Faults remove
// 3 m of the fence and 1.5 m of the stripe.
#include <gmock/gmock.h>
#include <grpcpp/create_channel.h>
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "absl/strings/str_split.h"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/scenario/child_process.hpp"
#include "fleetnav/v1/sim_service.grpc.pb.h"

namespace fleetnav {
namespace {

using scenario::ChildProcess;
using ::testing::HasSubstr;

constexpr char kHall[] = R"(name: fence-hall
extent: {min: [-15, -9], max: [15, 5]}
walls:
  - {from: [-15, -8.9], to: [15, -8.9], thickness: 0.2, height: 3.0}
  - {from: [-15, 4.9], to: [15, 4.9], thickness: 0.2, height: 3.0}
  - {from: [-14.9, -9], to: [-14.9, 5], thickness: 0.2, height: 3.0}
  - {from: [14.9, -9], to: [14.9, 5], thickness: 0.2, height: 3.0}
fences:
  - {from: [-12, 2.0], to: [12, 2.0], thickness: 0.1, height: 1.2}
boxes:
  - {center: [0, -7.2], size: [4, 0.8], height: 1.0, kind: feed_kitchen}
cylinders:
  - {center: [8.5, -5.0], radius: 0.15, height: 1.5, kind: charging_pole}
stripes:
  - {id: 5, points: [[-12, -5.0], [5.5, -5.0]]}
  - {id: 9, points: [[5.6, -5.0], [7.8, -5.0]], kind: charger}
markers:
  - {id: 1, at: [-4.0, 0.8], yaw_deg: 90, length: 0.6}
  - {id: 2, at: [4.0, 0.8], yaw_deg: 90, length: 0.6}
robots:
  - {id: lely1, kind: lely-vector, pose: [-10, 0.8, 0]}
  - {id: lely2, kind: lely-vector, pose: [-10, -5.0, 0]}
)";

constexpr char kGapFault[] = R"(faults:
  - {type: remove_fence, label: gap, region: {min: [-1.0, 1.8], max: [2.0, 2.2]}}
  - {type: remove_stripe, label: interruption, region: {min: [-3.0, -5.2], max: [-1.5, -4.8]}}
)";

/// One closed-loop run: a fresh directory, the world, its exported map, a simulator process.
class ClosedLoop : public ::testing::Test {
 protected:
  /// With `record_truth` the simulator records every robot's true track at 50 Hz to
  /// Path("truth.csv").
  /// The simulator on `world_file` (else the fence hall, with the gap fault if asked); the
  /// site's map is exported from `map_world_file` when given (a world without some obstacles).
  void StartSim(bool with_gap, uint64_t seed = 3, const std::string& world_file = "",
                bool record_truth = false, const std::string& map_world_file = "") {
    dir_ = std::filesystem::path(::testing::TempDir()) /
           ("closed-loop-" + std::to_string(getpid()) + "-" + std::to_string(file_counter++));
    // A folder of an earlier run with the same pid holds a stale sim.port.
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
    std::string world = Path("fence-hall.yaml");
    if (world_file.empty()) {
      std::ofstream(world) << kHall << (with_gap ? kGapFault : "");
    } else {
      world = world_file;
    }
    ChildProcess exporter(
        {FLEETNAV_SIM_PATH, "--world", map_world_file.empty() ? world : map_world_file,
         "--export-map", Path("map")},
        Path("export.out"), Path("export.err"));
    ASSERT_EQ(exporter.Wait(60.0), 0) << exporter.Stderr();
    // --export-map names its files after the world's name.
    for (const auto& entry : std::filesystem::directory_iterator(dir_ / "map")) {
      const std::string file = entry.path().filename().string();
      const std::string suffix = ".markers.yaml";
      if (file.size() > suffix.size() && file.ends_with(suffix)) {
        map_stem_ = file.substr(0, file.size() - suffix.size());
      }
    }
    std::vector<std::string> sim_args{FLEETNAV_SIM_PATH, "--world",     world,
                                      "--listen",        "127.0.0.1:0", "--port-file",
                                      Path("sim.port"),  "--seed",      std::to_string(seed)};
    if (record_truth) {
      sim_args.insert(sim_args.end(),
                      {"--record-truth", Path("truth.csv"), "--record-truth-hz", "50"});
    }
    sim_ = std::make_unique<ChildProcess>(sim_args, Path("sim.out"), Path("sim.err"));
    const int port = scenario::WaitForPortFile(Path("sim.port"));
    ASSERT_GT(port, 0) << sim_->Stderr();
    sim_address_ = "127.0.0.1:" + std::to_string(port);
  }

  std::string Path(const std::string& name) const { return (dir_ / name).string(); }

  std::string WriteRoute(const std::string& actions, const std::string& map = "fence-hall") {
    const std::string path = Path("route-" + std::to_string(file_counter++) + ".yaml");
    std::ofstream(path) << "name: hall-route\nmap: " << map << "\nactions:\n" << actions;
    return path;
  }

  /// Runs fleetnav-agent on `route` for lely1 and returns its exit code (-1: timed out).
  int RunAgent(const std::string& route, std::vector<std::string> extra = {},
               const std::string& kind = "lely-vector",
               std::vector<double> pose = {-10.02, 0.82, 0.5},
               const std::string& robot_id = "lely1") {
    std::vector<std::string> args = {FLEETNAV_AGENT_PATH,
                                     "--robot-id",
                                     robot_id,
                                     "--kind",
                                     kind,
                                     "--sim",
                                     sim_address_,
                                     "--server",
                                     "127.0.0.1:1",  // nothing listens there
                                     "--route",
                                     route,
                                     "--map",
                                     Path("map/" + map_stem_ + ".yaml"),
                                     "--markers",
                                     Path("map/" + map_stem_ + ".markers.yaml"),
                                     "--particles",
                                     "1000",
                                     "--initial-pose"};
    for (double v : pose) args.push_back(std::to_string(v));
    args.insert(args.end(), extra.begin(), extra.end());
    agent_ = std::make_unique<ChildProcess>(args, Path("agent.out"), Path("agent.err"));
    return agent_->Wait(240.0).value_or(-1);
  }

  v1::GroundTruth Truth() {
    auto stub = v1::SimService::NewStub(
        grpc::CreateChannel(sim_address_, grpc::InsecureChannelCredentials()));
    grpc::ClientContext context;
    context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(10));
    v1::GroundTruth truth;
    EXPECT_TRUE(stub->GetGroundTruth(&context, v1::GetGroundTruthRequest(), &truth).ok());
    return truth;
  }

  static const v1::RobotGroundTruth& Robot(const v1::GroundTruth& truth, const std::string& id) {
    for (const auto& r : truth.robots()) {
      if (r.robot_id() == id) return r;
    }
    ADD_FAILURE() << "no robot " << id;
    return truth.robots(0);
  }

  std::string AgentLog() const { return agent_ ? agent_->Stderr() + agent_->Stdout() : ""; }

  /// Runs a shipped route for lely1 from the middle of a shipped barn world and expects it
  /// docked by the truth: no contact, heading west on the charger stripe, the contact 5 cm short
  /// of the pole's face.
  void RunBarnRouteAndExpectDocked(const std::string& world, const std::string& route) {
    StartSim(false, 5, std::string(FLEETNAV_WORLDS_DIR) + "/" + world);
    ASSERT_EQ(RunAgent(std::string(FLEETNAV_ROUTES_DIR) + "/" + route, {}, "lely-vector",
                       {-5.48, 0.02, 0.5}),
              0)
        << AgentLog();
    const v1::RobotGroundTruth& lely = Robot(Truth(), "lely1");
    EXPECT_EQ(lely.collisions(), 0u) << AgentLog();
    EXPECT_NEAR(lely.pose().x_m(), -9.91, 0.05) << AgentLog();
    EXPECT_NEAR(lely.pose().y_m(), 0.0, 0.03) << AgentLog();
    EXPECT_GT(std::abs(lely.pose().yaw_rad()), 3.1);
  }

  void TearDown() override {
    if (sim_) sim_->Stop();
  }

  std::filesystem::path dir_;
  std::string map_stem_;
  std::string sim_address_;
  std::unique_ptr<ChildProcess> sim_;
  std::unique_ptr<ChildProcess> agent_;
  static inline int file_counter = 0;
};

// Fence navigation along 16 m of fence with a 3 m gap: reactive on the ultrasonic, map-based
// (SAMCL) through the gap, reactive again after it; the robot ends on its line at the distance.
TEST_F(ClosedLoop, FenceLegBridgesAGapAndEndsOnTheLine) {
  StartSim(/*with_gap=*/true);
  const std::string route = WriteRoute(
      "  - fence_navigation: {side: left, fence_distance: 0.9, distance: 16, speed: 0.3}\n");
  ASSERT_EQ(RunAgent(route), 0) << AgentLog();
  const v1::GroundTruth truth = Truth();
  const v1::RobotGroundTruth& lely = Robot(truth, "lely1");
  // The sensor line is 0.9 m from the fence face (y = 1.95): the robot at y = 0.8.
  EXPECT_NEAR(lely.pose().x_m(), 6.0, 0.2) << AgentLog();
  EXPECT_NEAR(lely.pose().y_m(), 0.8, 0.06) << AgentLog();
  EXPECT_LT(std::abs(lely.pose().yaw_rad()), 0.05);
  EXPECT_EQ(lely.collisions(), 0u);
  EXPECT_THAT(AgentLog(), HasSubstr("no echo from the left fence"));
  EXPECT_THAT(AgentLog(), HasSubstr("the fence answers again"));
}

// A straight that ends on marker 2 ends where the robot's own inductive sensor crossed it
// (sensor 0.485 m ahead of the axle: the axle at x ≈ 3.5 m), not at its 16 m.
TEST_F(ClosedLoop, StraightEndsOnTheMarkerTheAgentDetects) {
  StartSim(/*with_gap=*/false);
  const std::string route =
      WriteRoute("  - straight: {distance: 16, speed: 0.25}\n    until: {marker: 2}\n");
  ASSERT_EQ(RunAgent(route), 0) << AgentLog();
  const v1::RobotGroundTruth& lely = Robot(Truth(), "lely1");
  EXPECT_GT(lely.pose().x_m(), 3.4) << AgentLog();
  EXPECT_LT(lely.pose().x_m(), 3.9) << AgentLog();
  EXPECT_EQ(lely.collisions(), 0u);
  EXPECT_THAT(AgentLog(), HasSubstr("calibrated on marker 1"));
  EXPECT_THAT(AgentLog(), HasSubstr("calibrated on marker 2"));
}

// A slippery 4 m before marker 1 (the wheels keep 70 % of their traction) runs the odometry
// more than a metre ahead: the marker is still recognised (unambiguous within 2.5 m), the
// estimate jumps back, and the straight ends on marker 2 where the sensor truly crossed it.
TEST_F(ClosedLoop, SlipperyFloorBeforeAMarkerStillEndsOnTheNextMarker) {
  const std::string world = (std::filesystem::path(::testing::TempDir()) /
                             ("slippery-hall-" + std::to_string(getpid()) + ".yaml"))
                                .string();
  std::ofstream(world) << kHall
                       << "faults:\n  - {type: wheel_slip, region: {min: [-9, 0.2], max: [-5, "
                          "1.4]}, factor: 0.7}\n";
  StartSim(false, 3, world);
  const std::string route =
      WriteRoute("  - straight: {distance: 16, speed: 0.25}\n    until: {marker: 2}\n");
  ASSERT_EQ(RunAgent(route), 0) << AgentLog();
  const v1::RobotGroundTruth& lely = Robot(Truth(), "lely1");
  EXPECT_GT(lely.pose().x_m(), 3.4) << AgentLog();
  EXPECT_LT(lely.pose().x_m(), 3.9) << AgentLog();
  EXPECT_EQ(lely.collisions(), 0u);
  EXPECT_THAT(AgentLog(), HasSubstr("calibrated on marker 1"));
}

// Driving at the east wall: the bumper stops the robot, the action fails naming the reason and
// the agent exits 1; the robot is not pushing on through the wall.
TEST_F(ClosedLoop, BumperStopsTheRobotAndTheRouteFails) {
  StartSim(/*with_gap=*/false);
  const std::string route = WriteRoute("  - straight: {distance: 30, speed: 0.3}\n");
  EXPECT_EQ(RunAgent(route), 1) << AgentLog();
  EXPECT_THAT(AgentLog(), HasSubstr("actions[0] (straight): bumper pressed"));
  const v1::RobotGroundTruth& lely = Robot(Truth(), "lely1");
  EXPECT_LT(lely.pose().x_m(), 14.9 - 1.3);
  EXPECT_GT(lely.pose().x_m(), 12.0);
  EXPECT_NEAR(lely.velocity().vx_mps(), 0.0, 0.02);
}

// Stripe navigation to the stripe's end across a 1.5 m interruption (map-based on the stripe
// known from the marker set), then docking along the charger stripe until the charger contact
// closes: the robot stops at the pole without touching it.
TEST_F(ClosedLoop, StripeLegAcrossAnInterruptionThenDocksAtTheCharger) {
  StartSim(/*with_gap=*/true);
  const std::string route = WriteRoute(
      "  - stripe_navigation: {stripe: 5, distance: 0, speed: 0.25}\n"
      "    until: stripe_end\n"
      "  - dock: {target: charger}\n"
      "    until: charger_contact\n");
  ASSERT_EQ(RunAgent(route, {}, "lely-vector", {-10.01, -5.02, -0.5}, "lely2"), 0) << AgentLog();
  const v1::RobotGroundTruth& lely = Robot(Truth(), "lely2");
  // Contact 5 cm before the front (1.395 m ahead of the axle) meets the pole at x = 8.35.
  EXPECT_GT(lely.pose().x_m(), 6.80) << AgentLog();
  EXPECT_LT(lely.pose().x_m(), 6.96) << AgentLog();
  EXPECT_NEAR(lely.pose().y_m(), -5.0, 0.03) << AgentLog();
  EXPECT_EQ(lely.collisions(), 0u) << AgentLog();
  EXPECT_THAT(AgentLog(), HasSubstr("stripe 5 interrupted"));
  EXPECT_THAT(AgentLog(), HasSubstr("stripe 5 answers again"));
}

// The shipped feeding round on the shipped barn (every action type: free navigation, stripes,
// a straight, a turn, fence navigation along the feed kitchen, docking), on the barn with the
// error cases too: it completes, never touches anything, and ends on the charger.
class BarnFeedingRound : public ClosedLoop, public ::testing::WithParamInterface<const char*> {};

TEST_P(BarnFeedingRound, CompletesWithoutContactAndDocks) {
  RunBarnRouteAndExpectDocked(GetParam(), "barn_feeding.yaml");
}

INSTANTIATE_TEST_SUITE_P(Worlds, BarnFeedingRound,
                         ::testing::Values("barn.yaml", "barn_errors.yaml"));

// The thesis's Experiment 3 (deploy/routes/barn_exp3.yaml): both feeding fences, the north one
// through gap B into corner A, round the arc of case C onto stripe 3, back to the charger —
// on the barn and on the barn with the three error cases. Judged by the truth: docked without
// a contact; with the errors, the agent bridged B and C map-based.
class BarnExperiment3 : public ClosedLoop, public ::testing::WithParamInterface<const char*> {};

TEST_P(BarnExperiment3, CompletesWithoutContactAndDocks) {
  const std::string world = GetParam();
  RunBarnRouteAndExpectDocked(world, "barn_exp3.yaml");
  EXPECT_THAT(AgentLog(), HasSubstr("calibrated on marker 1"));
  if (world == "barn_errors.yaml") {
    EXPECT_THAT(AgentLog(), HasSubstr("action 3: no echo from the right fence"));
    EXPECT_THAT(AgentLog(), HasSubstr("action 5: stripe 3 interrupted"));
    EXPECT_THAT(AgentLog(), HasSubstr("action 5: stripe 3 answers again"));
  }
}

INSTANTIATE_TEST_SUITE_P(Worlds, BarnExperiment3,
                         ::testing::Values("barn.yaml", "barn_errors.yaml"));

TEST_F(ClosedLoop, WrongKindIsRefusedAtAttachNamingBoth) {
  StartSim(/*with_gap=*/false);
  const std::string route = WriteRoute("  - straight: {distance: 1, speed: 0.25}\n");
  EXPECT_EQ(RunAgent(route, {}, "mecanum-platform"), 1);
  EXPECT_THAT(AgentLog(), HasSubstr("mecanum-platform"));
  EXPECT_THAT(AgentLog(), HasSubstr("lely-vector"));
}

/// The true track of `robot_id` recorded by fleetnav-sim --record-truth: (x, y) per sample.
std::vector<Eigen::Vector2d> ReadTruthTrack(const std::string& path, const std::string& robot_id) {
  std::vector<Eigen::Vector2d> track;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> parts = absl::StrSplit(line, ',');
    if (parts.size() >= 5 && parts[0] == robot_id && parts[1] == "truth") {
      track.emplace_back(std::stod(parts[2]), std::stod(parts[3]));
    }
  }
  return track;
}

// The physical mecanum platform in the supermarket's aisle, on laser AMCL: sideways moves with
// reversals end where they started, and only with end-point augmentation does the platform
// carry on past a reversal point and bend round (KUKA thesis ch. 9).
TEST_F(ClosedLoop, MecanumSidewaysMovesBendRoundReversalsOnlyWithAugmentation) {
  double overshoot_m[2] = {0.0, 0.0};
  for (int augmented = 0; augmented < 2; ++augmented) {
    StartSim(false, 4, std::string(FLEETNAV_WORLDS_DIR) + "/supermarket.yaml",
             /*record_truth=*/true);
    const std::string route = WriteRoute(
        "  - move: {dx: 0, dy: 0.6, speed: 0.2}\n  - move: {dx: 0, dy: -0.6, speed: 0.2}\n"
        "  - move: {dx: 0, dy: 0.6, speed: 0.2}\n  - move: {dx: 0, dy: -0.6, speed: 0.2}\n",
        "supermarket");
    std::vector<std::string> extra;
    if (augmented == 0) extra.push_back("--no-endpoint-augmentation");
    ASSERT_EQ(RunAgent(route, extra, "mecanum-platform", {-8.0, 1.8, 0.0}, "omni1"), 0)
        << AgentLog();
    const v1::RobotGroundTruth& omni = Robot(Truth(), "omni1");
    EXPECT_EQ(omni.collisions(), 0);
    EXPECT_NEAR(omni.pose().x_m(), -8.0, 0.05) << "augmented " << augmented;
    EXPECT_NEAR(omni.pose().y_m(), 1.8, 0.05) << "augmented " << augmented;
    EXPECT_NEAR(omni.pose().yaw_rad(), 0.0, 0.03) << "augmented " << augmented;
    sim_->Stop();  // SIGTERM: the simulator closes its truth record
    const std::vector<Eigen::Vector2d> track = ReadTruthTrack(Path("truth.csv"), "omni1");
    ASSERT_GT(track.size(), 100u);
    for (const Eigen::Vector2d& p : track) {
      overshoot_m[augmented] = std::max(overshoot_m[augmented], p.y() - (1.8 + 0.6));
    }
  }
  EXPECT_LT(overshoot_m[0], 0.03);  // straight back from the reversal point
  EXPECT_GT(overshoot_m[1], 0.03);  // carried on and bent round
}

/// The shipped supermarket with its platform moved to `pose` (x y yaw_deg), written beside the
/// test's files.
std::string SupermarketWithPlatformAt(const std::string& dir, const std::string& pose) {
  std::ifstream in(std::string(FLEETNAV_WORLDS_DIR) + "/supermarket.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string from = "pose: [-8.0, 1.8, 0.0]";
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos);
  if (at != std::string::npos) text.replace(at, from.size(), "pose: [" + pose + "]");
  const std::string path = dir + "/supermarket-moved.yaml";
  std::ofstream(path) << text;
  return path;
}

// KUKA thesis ch. 15 in the loop: the platform finds trolley-2 by its legs, drives to the
// approach frame and under it, stops at its centre, touching nothing (truth), and its lift
// latches the trolley: the truth names the platform as its carrier.
TEST_F(ClosedLoop, MecanumDocksUnderATrolleyWithoutTouchingItsLegs) {
  const std::string world = SupermarketWithPlatformAt(::testing::TempDir(), "0.4, 1.5, 12.0");
  StartSim(false, 7, world);
  const std::string route =
      WriteRoute("  - dock: {target: trolley, target_id: trolley-2}\n", "supermarket");
  ASSERT_EQ(RunAgent(route, {}, "mecanum-platform", {0.4, 1.5, 12.0}, "omni1"), 0) << AgentLog();
  const v1::GroundTruth truth = Truth();
  const v1::RobotGroundTruth& omni = Robot(truth, "omni1");
  EXPECT_EQ(omni.collisions(), 0);
  EXPECT_NEAR(omni.pose().x_m(), 2.5, 0.01);
  EXPECT_NEAR(omni.pose().y_m(), 1.8, 0.01);
  EXPECT_NEAR(std::remainder(omni.pose().yaw_rad(), kPi), 0.0, 0.02);
  // The trolley (physical, it would roll away if touched) stands where it stood, on the lift.
  bool found = false;
  for (const v1::TrolleyGroundTruth& trolley : truth.trolleys()) {
    if (trolley.trolley_id() != "trolley-2") {
      EXPECT_EQ(trolley.carrier_robot_id(), "") << trolley.trolley_id();
      continue;
    }
    found = true;
    EXPECT_NEAR(trolley.pose().x_m(), 2.5, 0.005);
    EXPECT_NEAR(trolley.pose().y_m(), 1.8, 0.005);
    EXPECT_EQ(trolley.carrier_robot_id(), "omni1");
  }
  EXPECT_TRUE(found);
  // fleetnavctl shows the trolleys too.
  ChildProcess ctl({FLEETNAV_CTL_PATH, "--json", "sim", "--sim", sim_address_, "truth"},
                   Path("ctl.out"), Path("ctl.err"));
  ASSERT_EQ(ctl.Wait(30.0), 0) << ctl.Stderr();
  EXPECT_THAT(ctl.Stdout(), HasSubstr("\"trolley_id\":\"trolley-2\""));
  EXPECT_THAT(ctl.Stdout(), HasSubstr("\"carrier_robot_id\":\"omni1\""));
}

// A dock at a trolley the map does not have is refused before the robot moves; one the map has
// but the laser cannot see fails with the reason, the robot standing where it was.
TEST_F(ClosedLoop, TrolleyDocksNotOnTheMapOrNotInViewAreRefusedOrFail) {
  const std::string world = SupermarketWithPlatformAt(::testing::TempDir(), "0.4, 1.5, 12.0");
  StartSim(false, 7, world);
  EXPECT_EQ(
      RunAgent(WriteRoute("  - dock: {target: trolley, target_id: trolley-9}\n", "supermarket"), {},
               "mecanum-platform", {0.4, 1.5, 12.0}, "omni1"),
      1);
  EXPECT_THAT(AgentLog(), HasSubstr("trolley 'trolley-9' is not on map 'supermarket'"));
  EXPECT_EQ(
      RunAgent(WriteRoute("  - dock: {target: trolley, target_id: trolley-3}\n", "supermarket"), {},
               "mecanum-platform", {0.4, 1.5, 12.0}, "omni1"),
      1);
  EXPECT_THAT(AgentLog(), HasSubstr("trolley 'trolley-3' not in view"));
  const v1::RobotGroundTruth& omni = Robot(Truth(), "omni1");
  EXPECT_NEAR(omni.pose().x_m(), 0.4, 0.01);
  EXPECT_NEAR(omni.pose().y_m(), 1.5, 0.01);
}

// The shipped store round (deploy/routes/store_trolley_round.yaml): aisle, a sideways scan and
// back, under trolley-2, which it carries up the aisle and sets down, out from under it and
// home; judged by the truth: no contact (the carried trolley's count as the robot's), the
// trolley standing where the route set it down, carried by nobody.
TEST_F(ClosedLoop, ShippedStoreRoundEndsAtHomeWithoutContact) {
  StartSim(false, 11, std::string(FLEETNAV_WORLDS_DIR) + "/supermarket.yaml");
  ASSERT_EQ(RunAgent(std::string(FLEETNAV_ROUTES_DIR) + "/store_trolley_round.yaml", {},
                     "mecanum-platform", {-8.0, 1.8, 0.0}, "omni1"),
            0)
      << AgentLog();
  const v1::GroundTruth truth = Truth();
  const v1::RobotGroundTruth& omni = Robot(truth, "omni1");
  EXPECT_EQ(omni.collisions(), 0);
  EXPECT_NEAR(omni.pose().x_m(), -8.0, 0.1);
  EXPECT_NEAR(omni.pose().y_m(), 1.8, 0.1);
  bool found = false;
  for (const v1::TrolleyGroundTruth& trolley : truth.trolleys()) {
    if (trolley.trolley_id() != "trolley-2") continue;
    found = true;
    EXPECT_NEAR(trolley.pose().x_m(), -5.0, 0.1);
    EXPECT_NEAR(trolley.pose().y_m(), 1.8, 0.1);
    EXPECT_EQ(trolley.carrier_robot_id(), "");
  }
  EXPECT_TRUE(found);
}

// Another store (tests/scenarios/store_aisles): north-south aisles, one trolley along an aisle
// between shelf faces (whose corners make three-leg look-alikes), one at -30° in the open. The
// platform moves both, passing the first where it set it down (the map does not show it there),
// and goes home; judged by the truth: no contact, both trolleys standing where the route set
// them down, carried by nobody.
TEST_F(ClosedLoop, ATrolleyRoundInAStoreWithNorthSouthAisles) {
  const std::string dir = std::string(FLEETNAV_SCENARIOS_DIR) + "/store_aisles";
  StartSim(false, 13, dir + "/world.yaml");
  ASSERT_EQ(RunAgent(dir + "/round.yaml", {}, "mecanum-platform", {-6.5, -3.6, 0.0}, "omni1"), 0)
      << AgentLog();
  const v1::GroundTruth truth = Truth();
  const v1::RobotGroundTruth& omni = Robot(truth, "omni1");
  EXPECT_EQ(omni.collisions(), 0);
  EXPECT_NEAR(omni.pose().x_m(), -6.5, 0.1);
  EXPECT_NEAR(omni.pose().y_m(), 0.0, 0.1);
  const std::map<std::string, Eigen::Vector2d> set_down = {{"cart-a", {2.25, -3.3}},
                                                           {"cart-b", {-5.0, -3.5}}};
  int found = 0;
  for (const v1::TrolleyGroundTruth& trolley : truth.trolleys()) {
    const auto it = set_down.find(trolley.trolley_id());
    if (it == set_down.end()) continue;
    ++found;
    EXPECT_NEAR(trolley.pose().x_m(), it->second.x(), 0.1) << trolley.trolley_id();
    EXPECT_NEAR(trolley.pose().y_m(), it->second.y(), 0.1) << trolley.trolley_id();
    EXPECT_EQ(trolley.carrier_robot_id(), "");
  }
  EXPECT_EQ(found, 2);
}

// The shipped yard delivery (deploy/routes/yard_delivery.yaml): through the row of parcels with
// near-equal gaps (the capstone's §5.2 failure) to the loading dock and back; judged by the
// truth.
TEST_F(ClosedLoop, ShippedYardDeliveryPassesTheParcelRowAndReturnsWithoutContact) {
  StartSim(false, 12, std::string(FLEETNAV_WORLDS_DIR) + "/delivery_yard.yaml",
           /*record_truth=*/true);
  ASSERT_EQ(RunAgent(std::string(FLEETNAV_ROUTES_DIR) + "/yard_delivery.yaml", {},
                     "ackermann-delivery", {-16.0, 0.0, 0.0}, "delivery1"),
            0)
      << AgentLog();
  const v1::RobotGroundTruth& car = Robot(Truth(), "delivery1");
  EXPECT_EQ(car.collisions(), 0);
  EXPECT_NEAR(car.pose().x_m(), -16.0, 0.15);
  EXPECT_NEAR(car.pose().y_m(), 0.0, 0.15);
  // It crossed the parcel row (y = -4) between the parcels at x = -4.1 and -2.45.
  sim_->Stop();
  bool crossed = false;
  for (const Eigen::Vector2d& p : ReadTruthTrack(Path("truth.csv"), "delivery1")) {
    crossed |= std::abs(p.y() + 4.0) < 0.05 && p.x() > -3.8 && p.x() < -2.75;
  }
  EXPECT_TRUE(crossed);
}

// Another yard (tests/scenarios/yard_west_dock): through a north-south parcel row with
// near-equal gaps to a dock in the south-west and back, ending with a turn-round to face west
// where it started (a short manoeuvre with cusps the car used to overshoot back and forth).
// Judged by the truth: no contact, back at the start.
TEST_F(ClosedLoop, AnAckermannDeliveryInAYardWithAWestDock) {
  const std::string dir = std::string(FLEETNAV_SCENARIOS_DIR) + "/yard_west_dock";
  StartSim(false, 14, dir + "/world.yaml");
  ASSERT_EQ(
      RunAgent(dir + "/delivery.yaml", {}, "ackermann-delivery", {10.0, 0.0, 180.0}, "delivery1"),
      0)
      << AgentLog();
  const v1::RobotGroundTruth& car = Robot(Truth(), "delivery1");
  EXPECT_EQ(car.collisions(), 0);
  EXPECT_NEAR(car.pose().x_m(), 10.0, 0.15);
  EXPECT_NEAR(car.pose().y_m(), 0.0, 0.15);
}

// VFH+ in the loop (Ashesi capstone §5.2): a row of parcels with near-equal gaps stands across
// the Ackermann robot's way but is not on its map. It steers through a gap and on to the goal
// without a contact; followed blind (--no-obstacle-avoidance), the same route drives into the
// parcel on the line.
TEST_F(ClosedLoop, AckermannSteersThroughUnmappedParcelsWithVfhPlus) {
  const std::string yard =
      "name: parcel_yard\n"
      "extent: {min: [-10, -5], max: [10, 5]}\n"
      "fences:\n"
      "  - {from: [-10, -4.95], to: [10, -4.95], thickness: 0.1, height: 1.8}\n"
      "  - {from: [-10, 4.95], to: [10, 4.95], thickness: 0.1, height: 1.8}\n"
      "  - {from: [-9.95, -5], to: [-9.95, 5], thickness: 0.1, height: 1.8}\n"
      "  - {from: [9.95, -5], to: [9.95, 5], thickness: 0.1, height: 1.8}\n"
      "boxes:\n"
      "  - {center: [6.0, 3.0], size: [2.0, 1.0], height: 2.0, kind: building}\n";
  const std::string robots =
      "robots:\n"
      "  - {id: car1, kind: ackermann-delivery, pose: [-8.0, 0.2, 0.0]}\n";
  // Gaps of 1.05, 1.05, 1.10 and 1.00 m; the middle parcel stands on the straight line.
  const std::string parcels =
      "  - {center: [0.0, -3.3], size: [0.6, 0.6], height: 0.8, kind: parcel}\n"
      "  - {center: [0.0, -1.65], size: [0.6, 0.6], height: 0.8, kind: parcel}\n"
      "  - {center: [0.0, 0.0], size: [0.6, 0.6], height: 0.8, kind: parcel}\n"
      "  - {center: [0.0, 1.7], size: [0.6, 0.6], height: 0.8, kind: parcel}\n"
      "  - {center: [0.0, 3.3], size: [0.6, 0.6], height: 0.8, kind: parcel}\n";
  for (const bool avoid : {true, false}) {
    SCOPED_TRACE(avoid ? "VFH+" : "blind");
    dir_ = std::filesystem::path(::testing::TempDir()) /
           ("closed-loop-yard-" + std::to_string(getpid()) + "-" + std::to_string(avoid));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
    const std::string world = Path("parcel-yard.yaml");
    const std::string site = Path("parcel-yard-site.yaml");
    std::ofstream(world) << yard << parcels << robots;
    std::ofstream(site) << yard << robots;
    StartSim(false, 5, world, /*record_truth=*/true, site);
    const std::string route = Path("through.yaml");
    std::ofstream(route)
        << "name: through\nmap: parcel_yard\nactions:\n"
        << "  - free_navigation: {goal: {x: 8.0, y: 0.2, yaw_deg: 0}, speed: 0.5}\n";
    std::vector<std::string> extra;
    if (!avoid) extra.push_back("--no-obstacle-avoidance");
    const int exit_code = RunAgent(route, extra, "ackermann-delivery", {-8.0, 0.2, 0.0}, "car1");
    const v1::RobotGroundTruth car = Robot(Truth(), "car1");
    if (!avoid) {
      // It drives into the parcel (and may glance off it and still arrive).
      EXPECT_GT(car.collisions(), 0);
      sim_->Stop();
      continue;
    }
    ASSERT_EQ(exit_code, 0) << AgentLog();
    EXPECT_EQ(car.collisions(), 0);
    EXPECT_NEAR(car.pose().x_m(), 8.0, 0.15);
    EXPECT_NEAR(car.pose().y_m(), 0.2, 0.15);
    sim_->Stop();
    // It crossed the row (x = 0) in a gap beside the parcel on its line.
    std::optional<double> crossing_y;
    for (const Eigen::Vector2d& p : ReadTruthTrack(Path("truth.csv"), "car1")) {
      if (!crossing_y && p.x() >= 0.0) crossing_y = p.y();
    }
    ASSERT_TRUE(crossing_y.has_value());
    EXPECT_TRUE((*crossing_y > -1.35 && *crossing_y < -0.3) ||
                (*crossing_y > 0.3 && *crossing_y < 1.4))
        << *crossing_y;
  }
}

// A move on a robot that cannot translate sideways is refused before the robot moves.
TEST_F(ClosedLoop, MoveIsRefusedForTheLelyBeforeItMoves) {
  StartSim(/*with_gap=*/false);
  const std::string route = WriteRoute("  - move: {dx: 0, dy: 1.0}\n");
  EXPECT_EQ(RunAgent(route), 1);
  EXPECT_THAT(AgentLog(), HasSubstr("actions[0] (move): lely-vector cannot translate sideways"));
  const v1::RobotGroundTruth& lely = Robot(Truth(), "lely1");
  EXPECT_NEAR(lely.pose().x_m(), -10.0, 0.01);
}

// A route with an action this agent cannot run is refused before the robot moves.
TEST_F(ClosedLoop, UnrunnableRouteIsRefusedBeforeTheRobotMoves) {
  StartSim(/*with_gap=*/false);
  const std::string route =
      WriteRoute("  - straight: {distance: 2, speed: 0.25}\n  - dock: {target: trolley}\n");
  EXPECT_EQ(RunAgent(route), 1);
  EXPECT_THAT(AgentLog(), HasSubstr("actions[1] (dock)"));
  const v1::RobotGroundTruth& lely = Robot(Truth(), "lely1");
  EXPECT_NEAR(lely.pose().x_m(), -10.0, 0.01);
}

TEST_F(ClosedLoop, RouteOnAnotherMapIsRefusedBeforeTheRobotMoves) {
  StartSim(/*with_gap=*/false);
  const std::string route = Path("other-map.yaml");
  std::ofstream(route) << "name: elsewhere\nmap: barn\nactions:\n"
                       << "  - straight: {distance: 2, speed: 0.25}\n";
  EXPECT_EQ(RunAgent(route), 1);
  EXPECT_THAT(AgentLog(), HasSubstr("is on map 'barn'"));
  EXPECT_NEAR(Robot(Truth(), "lely1").pose().x_m(), -10.0, 0.01);
}

TEST_F(ClosedLoop, InitialPoseIsRequired) {
  StartSim(/*with_gap=*/false);
  const std::string route = WriteRoute("  - straight: {distance: 1, speed: 0.25}\n");
  ChildProcess agent(
      {FLEETNAV_AGENT_PATH, "--robot-id", "lely1", "--sim", sim_address_, "--route", route},
      Path("a.out"), Path("a.err"));
  EXPECT_EQ(agent.Wait(30.0), 1);
  EXPECT_THAT(agent.Stderr() + agent.Stdout(), HasSubstr("--initial-pose"));
}

// A fence leg where no fence is near (lely2 on the stripe, the fence 7 m north of it) is refused
// before the robot moves, naming the action and where it would have looked.
TEST_F(ClosedLoop, FenceLegWithNoFenceNearIsRefusedBeforeTheRobotMoves) {
  StartSim(/*with_gap=*/false);
  const std::string route = WriteRoute(
      "  - straight: {distance: 1, speed: 0.25}\n"
      "  - fence_navigation: {side: left, fence_distance: 0.9, distance: 5, speed: 0.25}\n");
  EXPECT_EQ(RunAgent(route, {}, "lely-vector", {-10.01, -5.02, -0.5}, "lely2"), 1);
  EXPECT_THAT(AgentLog(), HasSubstr("actions[1] (fence_navigation): no fence within 1.90 m"));
  const v1::RobotGroundTruth& lely = Robot(Truth(), "lely2");
  EXPECT_NEAR(lely.pose().x_m(), -10.0, 0.01);
  EXPECT_NEAR(lely.pose().y_m(), -5.0, 0.01);
}

// A goal that is free on the map but closed off (the strip north of the fence, fenced at both
// ends here) is refused before the robot moves.
TEST_F(ClosedLoop, UnreachableGoalIsRefusedBeforeTheRobotMoves) {
  std::string world = kHall;
  const std::string fences = "fences:\n";
  world.replace(world.find(fences), fences.size(),
                fences +
                    "  - {from: [12, 2.0], to: [14.9, 2.0], thickness: 0.1, height: 1.2}\n"
                    "  - {from: [-14.9, 2.0], to: [-12, 2.0], thickness: 0.1, height: 1.2}\n");
  const std::string file = (std::filesystem::path(::testing::TempDir()) /
                            ("closed-hall-" + std::to_string(getpid()) + ".yaml"))
                               .string();
  std::ofstream(file) << world;
  StartSim(false, 3, file);
  const std::string route =
      WriteRoute("  - free_navigation: {goal: {x: 0, y: 3.5, yaw_deg: 0}, speed: 0.3}\n");
  EXPECT_EQ(RunAgent(route), 1);
  EXPECT_THAT(AgentLog(),
              HasSubstr("actions[0] (free_navigation): (0.00, 3.50) cannot be reached"));
  EXPECT_NEAR(Robot(Truth(), "lely1").pose().x_m(), -10.0, 0.01);
}

// Wheels that cannot turn (the drive slowed to nothing): commanded motion, none measured — the
// stall stops the robot after 2 s and the action fails naming it; the route is not "done".
TEST_F(ClosedLoop, StalledDriveFailsTheAction) {
  StartSim(/*with_gap=*/false);
  {
    auto stub = v1::SimService::NewStub(
        grpc::CreateChannel(sim_address_, grpc::InsecureChannelCredentials()));
    grpc::ClientContext context;
    v1::InjectFaultRequest request;
    request.set_type(v1::FAULT_TYPE_SLOW_DOWN);
    request.set_robot_id("lely1");
    request.set_factor(0.0);
    v1::InjectFaultResponse response;
    ASSERT_TRUE(stub->InjectFault(&context, request, &response).ok());
  }
  const std::string route = WriteRoute("  - straight: {distance: 5, speed: 0.3}\n");
  EXPECT_EQ(RunAgent(route), 1) << AgentLog();
  EXPECT_THAT(AgentLog(), HasSubstr("actions[0] (straight): stalled"));
  const v1::RobotGroundTruth& lely = Robot(Truth(), "lely1");
  EXPECT_NEAR(lely.pose().x_m(), -10.0, 0.05);
  EXPECT_EQ(lely.collisions(), 0u);
}

// Started with a heading 90 deg off: the estimate drives north through the fence and out of the
// hall while the robot goes straight along the fence. Beams that contradict the map that way are
// left out (short readings are taken for unmapped robots), but an estimate off the map is no
// place for a robot: the localizer declares itself lost and the robot stops in a controlled way
// long before the end of its 16 m straight, touching nothing. (45 deg off is no longer a wrong
// start this hall can show: the estimate then crosses the fence and, weighed over the
// ultrasonic's cone, finds the north wall 0.9 m to its left just as the robot has the fence —
// a mirror image of the truth that every reading fits.)
TEST_F(ClosedLoop, LostLocalizationStopsTheRobot) {
  StartSim(/*with_gap=*/false);
  const std::string route = WriteRoute("  - straight: {distance: 16, speed: 0.3}\n");
  EXPECT_EQ(RunAgent(route, {}, "lely-vector", {-10.0, 0.8, 90.0}), 1) << AgentLog();
  EXPECT_THAT(AgentLog(), HasSubstr("actions[0] (straight): localization lost"));
  const v1::RobotGroundTruth& lely = Robot(Truth(), "lely1");
  EXPECT_LT(lely.pose().x_m(), -10.0 + 16.0 - 3.0) << AgentLog();
  EXPECT_NEAR(lely.velocity().vx_mps(), 0.0, 0.02);
  EXPECT_EQ(lely.collisions(), 0u);
}

// A watch at 0 Hz would flood the terminal: refused before anything is asked of a server.
TEST(FleetnavctlProcess, WatchRateMustBePositive) {
  const std::string dir = ::testing::TempDir();
  ChildProcess ctl({FLEETNAV_CTL_PATH, "--server", "127.0.0.1:1", "watch", "--rate-hz", "0"},
                   dir + "/ctl.out", dir + "/ctl.err");
  const std::optional<int> code = ctl.Wait(10.0);
  ASSERT_TRUE(code.has_value());
  EXPECT_NE(*code, 0);
  EXPECT_THAT(ctl.Stderr() + ctl.Stdout(), HasSubstr("--rate-hz"));
}

}  // namespace
}  // namespace fleetnav
