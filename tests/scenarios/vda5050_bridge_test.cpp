// fleetnav-vda5050 with a real Mosquitto on loopback, fleetnavd and simulated VDA 5050 vehicles
// (fleetnav-vda-vehicle), all as processes: a goal job driven to its end (judged by the
// vehicle's true pose), a cancel that stops the vehicle, malformed, stale and unknown messages
// left out without harm, and an order made while the broker is away.
#include <arpa/inet.h>
#include <gmock/gmock.h>
#include <grpcpp/create_channel.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <thread>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "fleetnav/scenario/child_process.hpp"
#include "fleetnav/v1/fleet_service.grpc.pb.h"
#include "fleetnav/vda5050/mqtt_client.hpp"
#include "testing/eventually.hpp"

namespace fleetnav {
namespace {

using fleetnav::testing::Eventually;

using scenario::ChildProcess;
using ::testing::HasSubstr;

std::string TempPath(const std::string& name) {
  return (std::filesystem::path(::testing::TempDir()) / absl::StrCat("vda-", getpid(), "-", name))
      .string();
}

int FreePort() {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address));
  socklen_t length = sizeof(address);
  getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length);
  close(fd);
  return ntohs(address.sin_port);
}

/// The vehicle's last true pose from its --truth file: x, y, yaw.
std::optional<std::array<double, 3>> LastTruth(const std::string& path) {
  std::ifstream in(path);
  std::string line, last;
  while (std::getline(in, line)) {
    if (!line.empty()) last = line;
  }
  const std::vector<std::string> fields = absl::StrSplit(last, ',');
  if (fields.size() < 5) return std::nullopt;
  return std::array<double, 3>{std::stod(fields[1]), std::stod(fields[2]), std::stod(fields[3])};
}

/// Mosquitto, fleetnavd, the bridge and one simulated vehicle at (2, 2) on a 20 x 20 m floor.
class VdaBridgeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    mqtt_port_ = FreePort();
    StartBroker();
    ASSERT_GT(StartServer(), 0);
    fleet_ = v1::FleetService::NewStub(grpc::CreateChannel(absl::StrCat("127.0.0.1:", server_port_),
                                                           grpc::InsecureChannelCredentials()));
    PutFloor();
    bridge_ = std::make_unique<ChildProcess>(
        std::vector<std::string>{FLEETNAV_VDA5050_PATH, "--broker-port", absl::StrCat(mqtt_port_),
                                 "--server", absl::StrCat("127.0.0.1:", server_port_),
                                 "--stats-period-s", "1"},
        TempPath("bridge.out"), TempPath("bridge.log"));
    std::filesystem::remove(TempPath("truth.csv"));
    vehicle_ = std::make_unique<ChildProcess>(
        std::vector<std::string>{FLEETNAV_VDA_VEHICLE_PATH, "--broker-port",
                                 absl::StrCat(mqtt_port_), "--map", "floor", "--start", "2", "2",
                                 "0", "--speed-mps", "1.0", "--truth", TempPath("truth.csv")},
        TempPath("vehicle.out"), TempPath("vehicle.log"));
    ASSERT_TRUE(Eventually([&] { return RobotOnline("vda-acme-0001"); }, 20.0))
        << bridge_->Stderr() << vehicle_->Stderr();
  }
  void TearDown() override {
    if (vehicle_) vehicle_->Stop(SIGTERM, 5.0);
    if (bridge_) bridge_->Stop(SIGTERM, 5.0);
    if (server_) server_->Stop(SIGTERM, 10.0);
    if (broker_) broker_->Stop(SIGTERM, 5.0);
  }

  void StartBroker() {
    const std::string config = TempPath("mosquitto.conf");
    std::ofstream(config) << "listener " << mqtt_port_ << " 127.0.0.1\nallow_anonymous true\n"
                          << "persistence false\n";
    broker_ = std::make_unique<ChildProcess>(
        std::vector<std::string>{"/usr/sbin/mosquitto", "-c", config}, TempPath("mosquitto.out"),
        TempPath("mosquitto.log"));
    ASSERT_TRUE(Eventually(
        [&] {
          const int fd = socket(AF_INET, SOCK_STREAM, 0);
          sockaddr_in address{};
          address.sin_family = AF_INET;
          address.sin_port = htons(static_cast<uint16_t>(mqtt_port_));
          address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
          const bool up = connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)) == 0;
          close(fd);
          return up;
        },
        10.0))
        << "mosquitto did not start: " << broker_->Stderr();
  }

  int StartServer() {
    const std::string port_file = TempPath("server.port");
    std::filesystem::remove(port_file);
    for (const char* suffix : {"", "-wal", "-shm"})
      std::filesystem::remove(TempPath("fleet.db") + suffix);
    server_ = std::make_unique<ChildProcess>(
        std::vector<std::string>{FLEETNAV_FLEETNAVD_PATH, "--insecure", "--db",
                                 TempPath("fleet.db"), "--listen", "127.0.0.1:0", "--port-file",
                                 port_file},
        TempPath("fleetnavd.out"), TempPath("fleetnavd.log"));
    server_port_ = scenario::WaitForPortFile(port_file);
    return server_port_;
  }

  void PutFloor() {
    v1::PutMapRequest request;
    request.set_map_id("floor");
    request.mutable_grid()->set_width(200);
    request.mutable_grid()->set_height(200);
    request.mutable_grid()->set_resolution_m(0.1);
    request.mutable_grid()->set_cells(std::string(200 * 200, '\0'));
    grpc::ClientContext context;
    v1::PutMapResponse response;
    ASSERT_TRUE(fleet_->PutMap(&context, request, &response).ok());
  }

  bool RobotOnline(const std::string& robot_id) {
    grpc::ClientContext context;
    v1::GetRobotRequest request;
    request.set_robot_id(robot_id);
    v1::GetRobotResponse response;
    return fleet_->GetRobot(&context, request, &response).ok() &&
           response.robot().connection() == v1::CONNECTION_STATE_ONLINE;
  }

  std::string SubmitGoal(double x, double y, double yaw_rad) {
    v1::SubmitJobRequest request;
    request.mutable_goal()->set_map_id("floor");
    request.mutable_goal()->mutable_goal()->set_x_m(x);
    request.mutable_goal()->mutable_goal()->set_y_m(y);
    request.mutable_goal()->mutable_goal()->set_yaw_rad(yaw_rad);
    request.set_robot_id("vda-acme-0001");
    grpc::ClientContext context;
    v1::SubmitJobResponse response;
    const grpc::Status status = fleet_->SubmitJob(&context, request, &response);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return response.job().job_id();
  }

  v1::JobState JobState(const std::string& job_id) {
    grpc::ClientContext context;
    v1::GetJobRequest request;
    request.set_job_id(job_id);
    v1::GetJobResponse response;
    if (!fleet_->GetJob(&context, request, &response).ok()) return v1::JOB_STATE_UNSPECIFIED;
    return response.job().state();
  }

  /// Waits until the vehicle's true x passes `x_m`.
  bool TruthReaches(double x_m, double timeout_s) {
    return Eventually(
        [&] {
          const std::optional<std::array<double, 3>> truth = LastTruth(TempPath("truth.csv"));
          return truth && (*truth)[0] > x_m;
        },
        timeout_s);
  }

  /// After a command that should stop the vehicle: lets it brake (0.7 s), then checks that its
  /// true x does not change for `for_s`; returns where it stands.
  double StandingX(double for_s) {
    std::this_thread::sleep_for(std::chrono::milliseconds(700));
    const double x_m = (*LastTruth(TempPath("truth.csv")))[0];
    std::this_thread::sleep_for(std::chrono::milliseconds(static_cast<int>(for_s * 1e3)));
    EXPECT_NEAR((*LastTruth(TempPath("truth.csv")))[0], x_m, 1e-6) << "still moving";
    return x_m;
  }

  bool JobEndsAs(const std::string& job_id, v1::JobState state, double timeout_s) {
    return Eventually([&] { return JobState(job_id) == state; }, timeout_s);
  }

  int mqtt_port_ = 0;
  int server_port_ = 0;
  std::unique_ptr<ChildProcess> broker_;
  std::unique_ptr<ChildProcess> server_;
  std::unique_ptr<ChildProcess> bridge_;
  std::unique_ptr<ChildProcess> vehicle_;
  std::unique_ptr<v1::FleetService::Stub> fleet_;
};

TEST_F(VdaBridgeTest, AGoalJobIsDrivenToItsEndByTheVdaVehicle) {
  const std::string job = SubmitGoal(8.0, 7.0, 1.57);
  ASSERT_TRUE(JobEndsAs(job, v1::JOB_STATE_SUCCEEDED, 60.0))
      << JobState(job) << bridge_->Stderr() << vehicle_->Stderr();
  // The truth is recorded at 10 Hz: its line of the end may follow the success by 0.1 s.
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const std::optional<std::array<double, 3>> truth = LastTruth(TempPath("truth.csv"));
  ASSERT_TRUE(truth.has_value());
  EXPECT_NEAR((*truth)[0], 8.0, 0.1);
  EXPECT_NEAR((*truth)[1], 7.0, 0.1);
  EXPECT_NEAR((*truth)[2], 1.57, 0.05);
  EXPECT_THAT(bridge_->Stderr(), HasSubstr("sent to vda-acme-0001 as order"));
  EXPECT_THAT(vehicle_->Stdout(), HasSubstr("first_motion"));
}

TEST_F(VdaBridgeTest, ACancelStopsTheVehicleWhereItIs) {
  const std::string job = SubmitGoal(15.0, 2.0, 0.0);
  ASSERT_TRUE(TruthReaches(4.0, 30.0));
  grpc::ClientContext context;
  v1::CancelJobRequest cancel;
  cancel.set_job_id(job);
  v1::CancelJobResponse cancelled;
  ASSERT_TRUE(fleet_->CancelJob(&context, cancel, &cancelled).ok());
  const double stopped_x = StandingX(2.0);
  EXPECT_LT(stopped_x, 14.0);
  EXPECT_EQ(JobState(job), v1::JOB_STATE_CANCELLED);
  // The vehicle is free for the next job.
  const std::string next = SubmitGoal(stopped_x, 5.0, 0.0);
  EXPECT_TRUE(JobEndsAs(next, v1::JOB_STATE_SUCCEEDED, 60.0)) << bridge_->Stderr();
}

// An operator's pause becomes startPause: the vehicle stands; resume (stopPause) lets it finish.
TEST_F(VdaBridgeTest, APauseHoldsTheVehicleAndAResumeLetsItFinish) {
  const std::string job = SubmitGoal(15.0, 2.0, 0.0);
  ASSERT_TRUE(TruthReaches(4.0, 30.0));
  {
    grpc::ClientContext context;
    v1::PauseJobRequest pause;
    pause.set_job_id(job);
    v1::PauseJobResponse paused;
    ASSERT_TRUE(fleet_->PauseJob(&context, pause, &paused).ok());
  }
  const double held_x = StandingX(1.5);
  EXPECT_LT(held_x, 14.0);
  {
    grpc::ClientContext context;
    v1::ResumeJobRequest resume;
    resume.set_job_id(job);
    v1::ResumeJobResponse resumed;
    ASSERT_TRUE(fleet_->ResumeJob(&context, resume, &resumed).ok());
  }
  ASSERT_TRUE(JobEndsAs(job, v1::JOB_STATE_SUCCEEDED, 60.0)) << bridge_->Stderr();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_NEAR((*LastTruth(TempPath("truth.csv")))[0], 15.0, 0.1);
}

TEST_F(VdaBridgeTest, MalformedStaleAndUnknownMessagesAreLeftOutAndTheBridgeGoesOn) {
  absl::StatusOr<std::unique_ptr<vda5050::MosquittoClient>> intruder =
      vda5050::MosquittoClient::Connect({"127.0.0.1", mqtt_port_, "intruder"}, nullptr, nullptr);
  ASSERT_TRUE(intruder.ok()) << intruder.status();
  const std::string state_topic = "uagv/v2/acme/0001/state";
  ASSERT_TRUE((*intruder)->Publish(state_topic, "{not json", 1, false).ok());
  ASSERT_TRUE(
      (*intruder)
          ->Publish(state_topic,
                    R"({"headerId": 0, "timestamp": "2026-11-26T05:40:03Z", )"
                    R"("version": "2.0.0", "manufacturer": "acme", "serialNumber": "0001"})",
                    1, false)
          .ok());
  // A complete state of an unknown vehicle.
  std::ifstream ignored;
  ASSERT_TRUE((*intruder)
                  ->Publish("uagv/v2/ghost/0009/state",
                            R"({"headerId": 1, "timestamp": "2026-11-26T05:40:03.1Z", )"
                            R"("version": "2.0.0", "manufacturer": "ghost", "serialNumber": )"
                            R"("0009", "orderId": "", "orderUpdateId": 0, "lastNodeId": "", )"
                            R"("lastNodeSequenceId": 0, "nodeStates": [], "edgeStates": [], )"
                            R"("driving": false, "actionStates": [], "batteryState": )"
                            R"({"batteryCharge": 50, "charging": false}, "operatingMode": )"
                            R"("AUTOMATIC", "errors": [], "safetyState": {"eStop": "NONE", )"
                            R"("fieldViolation": false}})",
                            1, false)
                  .ok());
  ASSERT_TRUE(Eventually(
      [&] {
        const std::string log = bridge_->Stderr();
        return log.find("refused state: state: not JSON") != std::string::npos &&
               log.find("state.orderId: required string (§6.10.6)") != std::string::npos &&
               log.find("from ghost/0009, which never said it is online") != std::string::npos;
      },
      10.0))
      << bridge_->Stderr();
  EXPECT_TRUE(bridge_->running());
  // Still bridging: a job runs to its end.
  const std::string job = SubmitGoal(4.0, 4.0, 0.0);
  EXPECT_TRUE(JobEndsAs(job, v1::JOB_STATE_SUCCEEDED, 60.0)) << bridge_->Stderr();
  EXPECT_FALSE(RobotOnline("vda-ghost-0009"));
}

// The broker is down when fleetnavd assigns the job: the bridge's order cannot go out, and is
// sent when the broker is back; the vehicle then drives it to the end.
TEST_F(VdaBridgeTest, AnOrderMadeWhileTheBrokerIsAwayIsSentWhenItIsBack) {
  broker_->Stop(SIGKILL, 5.0);
  const std::string job = SubmitGoal(10.0, 12.0, 0.0);
  ASSERT_TRUE(Eventually(
      [&] {
        return JobState(job) == v1::JOB_STATE_ASSIGNED || JobState(job) == v1::JOB_STATE_RUNNING;
      },
      10.0));
  std::this_thread::sleep_for(std::chrono::seconds(1));
  StartBroker();
  EXPECT_TRUE(JobEndsAs(job, v1::JOB_STATE_SUCCEEDED, 90.0))
      << JobState(job) << bridge_->Stderr() << vehicle_->Stderr();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const std::optional<std::array<double, 3>> truth = LastTruth(TempPath("truth.csv"));
  ASSERT_TRUE(truth.has_value());
  EXPECT_NEAR((*truth)[0], 10.0, 0.1);
  EXPECT_NEAR((*truth)[1], 12.0, 0.1);
  EXPECT_THAT(bridge_->Stderr(), HasSubstr("broker back"));
}

}  // namespace
}  // namespace fleetnav
