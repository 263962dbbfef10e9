// fleetnavd replicas sharing one PostgreSQL database, run as processes: every replica serves
// the whole API by relaying to the site's leader; a robot connected through one replica is seen
// through the others; a job submitted twice through two replicas with one idempotency key is
// one job; when the leader is killed (SIGKILL) another replica takes the site over and the
// robot's stream comes back through a survivor; a database newer than the binary, and an SQLite
// file, are refused at start.
#include <gmock/gmock.h>
#include <grpcpp/create_channel.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/proto/telemetry_convert.hpp"
#include "fleetnav/scenario/child_process.hpp"
#include "fleetnav/storage/postgres/pg_database.hpp"
#include "fleetnav/storage/postgres/pg_schema.hpp"
#include "fleetnav/v1/agent_service.grpc.pb.h"
#include "fleetnav/v1/fleet_service.grpc.pb.h"
#include "postgres_server.hpp"
#include "testing/eventually.hpp"

namespace fleetnav {
namespace {

using fleetnav::testing::Eventually;

using scenario::ChildProcess;
using ::testing::HasSubstr;
using AgentStream = grpc::ClientReaderWriter<v1::AgentMessage, v1::ServerMessage>;

std::string TempPath(const std::string& name) {
  return (std::filesystem::path(::testing::TempDir()) /
          absl::StrCat("replica-", getpid(), "-", name))
      .string();
}

/// fleetnavd replicas on one database; replica i logs to replica-<pid>-<tag>-<i>.<start>.out.
class ReplicaSet {
 public:
  ReplicaSet(std::string db_uri, std::string tag) : db_uri_(std::move(db_uri)), tag_(tag) {}

  /// Starts replica `i` (again on its old port after a kill); returns its port (0: failed).
  int Start(size_t i) {
    if (replicas_.size() <= i) replicas_.resize(i + 1);
    Replica& replica = replicas_[i];
    ++replica.starts;
    const std::string port_file = TempPath(absl::StrCat(tag_, "-", i, ".port"));
    std::filesystem::remove(port_file);
    replica.process = std::make_unique<ChildProcess>(
        std::vector<std::string>{FLEETNAV_FLEETNAVD_PATH, "--insecure", "--replica", "--db",
                                 db_uri_, "--listen", absl::StrCat("127.0.0.1:", replica.port),
                                 "--port-file", port_file},
        Log(i), TempPath(absl::StrCat(tag_, "-", i, ".", replica.starts, ".err")));
    replica.port = scenario::WaitForPortFile(port_file);
    return replica.port;
  }
  void Kill(size_t i) { replicas_[i].process->Stop(SIGKILL, 5.0); }
  void Signal(size_t i, int signal) { ::kill(replicas_[i].process->pid(), signal); }
  std::optional<int> WaitForExit(size_t i, double timeout_s) {
    return replicas_[i].process->Wait(timeout_s);
  }
  std::string Log(size_t i) const {
    return TempPath(absl::StrCat(tag_, "-", i, ".", replicas_[i].starts, ".out"));
  }
  std::string Address(size_t i) const { return absl::StrCat("127.0.0.1:", replicas_[i].port); }
  std::shared_ptr<grpc::Channel> Channel(size_t i) const {
    return grpc::CreateChannel(Address(i), grpc::InsecureChannelCredentials());
  }

 private:
  struct Replica {
    std::unique_ptr<ChildProcess> process;
    int port = 0;
    int starts = 0;
  };
  std::string db_uri_;
  std::string tag_;
  std::vector<Replica> replicas_;
};

std::string NewDatabase(const std::string& stem) {
  absl::StatusOr<std::string> uri = fleetnav::testing::NewSharedDatabase(stem);
  EXPECT_TRUE(uri.ok()) << uri.status();
  return uri.value_or("");
}

std::optional<v1::RobotState> RobotThrough(v1::FleetService::Stub& fleet,
                                           const std::string& robot_id) {
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(2));
  v1::ListRobotsResponse robots;
  if (!fleet.ListRobots(&context, v1::ListRobotsRequest{}, &robots).ok()) return std::nullopt;
  for (const v1::RobotState& robot : robots.robots()) {
    if (robot.robot_id() == robot_id) return robot;
  }
  return std::nullopt;
}

/// An agent's stream through one replica: hello, then the welcome.
struct AgentSession {
  grpc::ClientContext context;
  std::unique_ptr<AgentStream> stream;
  bool welcomed = false;
};

std::unique_ptr<AgentSession> Connect(v1::AgentService::Stub& agents, const std::string& robot_id) {
  auto session = std::make_unique<AgentSession>();
  session->stream = agents.Connect(&session->context);
  v1::AgentMessage hello;
  *hello.mutable_hello() =
      ToProto(RobotIdentity{robot_id, LelyVectorModel(), {"free_navigation"}, "test"});
  v1::ServerMessage welcome;
  session->welcomed =
      session->stream->Write(hello) && session->stream->Read(&welcome) && welcome.has_welcome();
  return session;
}

/// A 20 x 20 m free map.
v1::PutMapRequest OpenFloor(const std::string& map_id) {
  v1::PutMapRequest request;
  request.set_map_id(map_id);
  v1::OccupancyGrid* grid = request.mutable_grid();
  grid->set_width(200);
  grid->set_height(200);
  grid->set_resolution_m(0.1);
  grid->set_cells(std::string(200 * 200, '\0'));
  return request;
}

TEST(ReplicaTest, EveryReplicaServesTheSiteAndTheLeaderKilledIsReplaced) {
  ReplicaSet replicas(NewDatabase("replicas"), "site");
  ASSERT_GT(replicas.Start(0), 0);
  ASSERT_GT(replicas.Start(1), 0);
  auto fleet0 = v1::FleetService::NewStub(replicas.Channel(0));
  auto fleet1 = v1::FleetService::NewStub(replicas.Channel(1));
  auto agents1 = v1::AgentService::NewStub(replicas.Channel(1));
  // Replica 0 started first and leads; replica 1 answers once it knows so.
  ASSERT_TRUE(Eventually(
      [&] {
        grpc::ClientContext context;
        v1::ListRobotsResponse robots;
        return fleet1->ListRobots(&context, v1::ListRobotsRequest{}, &robots).ok();
      },
      20.0));

  // A robot connected through replica 1 is online through replica 0.
  std::unique_ptr<AgentSession> robot = Connect(*agents1, "lely7");
  ASSERT_TRUE(robot->welcomed);
  ASSERT_TRUE(Eventually(
      [&] {
        const std::optional<v1::RobotState> seen = RobotThrough(*fleet0, "lely7");
        return seen && seen->connection() == v1::CONNECTION_STATE_ONLINE;
      },
      10.0));

  // WatchFleet through a follower (a relayed server stream) shows the robot in its snapshot.
  {
    grpc::ClientContext context;
    context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(5));
    auto watch = fleet1->WatchFleet(&context, v1::WatchFleetRequest{});
    v1::FleetUpdate update;
    ASSERT_TRUE(watch->Read(&update));
    EXPECT_TRUE(update.snapshot());
    bool seen = false;
    for (const v1::RobotState& robot : update.robots()) seen = seen || robot.robot_id() == "lely7";
    EXPECT_TRUE(seen);
    context.TryCancel();
  }

  // A map put through one replica; one job submitted through both with one key.
  {
    grpc::ClientContext context;
    v1::PutMapResponse put;
    const grpc::Status status = fleet1->PutMap(&context, OpenFloor("floor"), &put);
    ASSERT_TRUE(status.ok()) << status.error_message();
  }
  v1::SubmitJobRequest submit;
  submit.mutable_goal()->set_map_id("floor");
  submit.mutable_goal()->mutable_goal()->set_x_m(5.0);
  submit.mutable_goal()->mutable_goal()->set_y_m(5.0);
  submit.set_robot_id("lely7");
  submit.set_idempotency_key("replica-test-1");
  std::string job_ids[2];
  for (int i = 0; i < 2; ++i) {
    grpc::ClientContext context;
    v1::SubmitJobResponse response;
    const grpc::Status status = (i == 0 ? fleet0 : fleet1)->SubmitJob(&context, submit, &response);
    ASSERT_TRUE(status.ok()) << status.error_message();
    job_ids[i] = response.job().job_id();
  }
  EXPECT_EQ(job_ids[0], job_ids[1]);

  // The leader killed: the robot's relayed stream ends, and once replica 1 has taken the site
  // over the robot is back through it, with its job.
  replicas.Kill(0);
  v1::ServerMessage message;
  while (robot->stream->Read(&message)) {
  }
  EXPECT_FALSE(robot->stream->Finish().ok());
  std::unique_ptr<AgentSession> again;
  ASSERT_TRUE(Eventually(
      [&] {
        again = Connect(*agents1, "lely7");
        return again->welcomed;
      },
      15.0));
  EXPECT_THAT(scenario::ReadWholeFile(replicas.Log(1)), HasSubstr("leading at epoch 2"));
  ASSERT_TRUE(Eventually(
      [&] {
        const std::optional<v1::RobotState> seen = RobotThrough(*fleet1, "lely7");
        return seen && seen->connection() == v1::CONNECTION_STATE_ONLINE;
      },
      10.0));
  grpc::ClientContext context;
  v1::GetJobRequest get;
  get.set_job_id(job_ids[0]);
  v1::GetJobResponse job;
  ASSERT_TRUE(fleet1->GetJob(&context, get, &job).ok());
  EXPECT_EQ(job.job().job_id(), job_ids[0]);

  // The killed replica comes back as a follower and serves again, relaying to the new leader.
  ASSERT_GT(replicas.Start(0), 0);
  auto fleet0_again = v1::FleetService::NewStub(replicas.Channel(0));
  EXPECT_TRUE(Eventually(
      [&] {
        const std::optional<v1::RobotState> seen = RobotThrough(*fleet0_again, "lely7");
        return seen && seen->connection() == v1::CONNECTION_STATE_ONLINE;
      },
      15.0));
  again->context.TryCancel();
}

// The two-robot barn on three replicas, the leader killed while lely2 drives and lely1 waits
// for it: judged by the simulator's ground truth, both rounds end without contact and the
// robots never came closer than the coordination allows, so no robot was cleared into the
// other's way across the takeover; each job is one job.
TEST(ReplicaTest, TheBarnGoesOnWhenTheLeadingReplicaIsKilledMidJob) {
  const std::string keep = TempPath("failover-keep");
  std::filesystem::remove_all(keep);
  ChildProcess run({FLEETNAV_SCENARIO_PATH, "run",
                    std::string(FLEETNAV_SCENARIOS_DIR) + "/barn_leader_failover.yaml", "--json",
                    "--keep", keep, "--db", NewDatabase("failover")},
                   TempPath("failover.out"), TempPath("failover.err"));
  const std::optional<int> code = run.Wait(900.0);
  ASSERT_TRUE(code.has_value()) << "the scenario did not end in 15 min";
  const std::string out = run.Stdout();
  ASSERT_FALSE(out.empty()) << run.Stderr();
  std::printf("[ figures  ] %s\n", out.c_str());
  const nlohmann::json report = nlohmann::json::parse(out.substr(0, out.find('\n')));
  EXPECT_EQ(*code, 0) << run.Stderr();
  EXPECT_TRUE(report.value("passed", false)) << report["failures"].dump();
  EXPECT_EQ(report.value("contacts", -1), 0);
  EXPECT_GE(report.value("min_separation_m", 0.0), 0.5);
  ASSERT_EQ(report["jobs"].size(), 2u);
  EXPECT_NE(report["jobs"][0]["job_id"], report["jobs"][1]["job_id"]);
  for (const auto& job : report["jobs"]) EXPECT_EQ(job["state"], "succeeded") << job.dump();
  // One takeover was seen, and the killed replica came back.
  EXPECT_EQ(report["failovers_s"].size(), 1u);
  EXPECT_TRUE(std::filesystem::exists(keep + "/fleetnavd-r0.2.out") ||
              std::filesystem::exists(keep + "/fleetnavd-r1.2.out") ||
              std::filesystem::exists(keep + "/fleetnavd-r2.2.out"));
}

// A leader paused (SIGSTOP) past its lease is replaced; woken up, it finds its lease taken and
// exits with code 3 instead of leading beside its successor.
TEST(ReplicaTest, ALeaderPausedPastItsLeaseExitsWhenItWakes) {
  ReplicaSet replicas(NewDatabase("paused"), "paused");
  ASSERT_GT(replicas.Start(0), 0);
  ASSERT_TRUE(Eventually(
      [&] {
        return scenario::ReadWholeFile(replicas.Log(0)).find("leading at epoch 1") !=
               std::string::npos;
      },
      10.0));
  ASSERT_GT(replicas.Start(1), 0);
  replicas.Signal(0, SIGSTOP);
  ASSERT_TRUE(Eventually(
      [&] {
        return scenario::ReadWholeFile(replicas.Log(1)).find("leading at epoch 2") !=
               std::string::npos;
      },
      15.0));
  replicas.Signal(0, SIGCONT);
  const std::optional<int> code = replicas.WaitForExit(0, 10.0);
  ASSERT_TRUE(code.has_value()) << "the old leader kept running";
  EXPECT_EQ(*code, 3);
  EXPECT_THAT(scenario::ReadWholeFile(replicas.Log(0)), HasSubstr("leadership lost"));
  // The successor serves on.
  auto fleet1 = v1::FleetService::NewStub(replicas.Channel(1));
  EXPECT_TRUE(Eventually(
      [&] {
        grpc::ClientContext context;
        v1::ListRobotsResponse robots;
        return fleet1->ListRobots(&context, v1::ListRobotsRequest{}, &robots).ok();
      },
      10.0));
}

TEST(ReplicaTest, ADatabaseOfANewerSchemaIsRefusedNamingBothVersions) {
  const std::string uri = NewDatabase("newer");
  {
    absl::StatusOr<std::unique_ptr<storage::PgDatabase>> db =
        storage::PgDatabase::Open(uri, storage::PostgresFleetSchemaMigrations());
    ASSERT_TRUE(db.ok()) << db.status();
    ASSERT_TRUE((*db)
                    ->Transaction([&]() -> absl::Status {
                      absl::StatusOr<storage::SqlStatement> bump =
                          (*db)->Prepare("UPDATE fleetnav_schema SET version = 99");
                      if (!bump.ok()) return bump.status();
                      return bump->Run();
                    })
                    .ok());
  }
  ChildProcess replica(
      {FLEETNAV_FLEETNAVD_PATH, "--insecure", "--replica", "--db", uri, "--listen", "127.0.0.1:0"},
      TempPath("newer.out"), TempPath("newer.err"));
  const std::optional<int> code = replica.Wait(30.0);
  ASSERT_TRUE(code.has_value());
  EXPECT_EQ(*code, 1);
  const std::string said = replica.Stdout() + replica.Stderr();
  EXPECT_THAT(said, HasSubstr("schema version 99 is newer than this binary's"));
  EXPECT_THAT(said, HasSubstr(absl::StrCat(storage::PostgresFleetSchemaMigrations().size())));
}

TEST(ReplicaTest, ReplicasOnAnSqliteFileAreRefused) {
  ChildProcess replica({FLEETNAV_FLEETNAVD_PATH, "--insecure", "--replica", "--db",
                        TempPath("fleet.db"), "--listen", "127.0.0.1:0"},
                       TempPath("sqlite.out"), TempPath("sqlite.err"));
  const std::optional<int> code = replica.Wait(30.0);
  ASSERT_TRUE(code.has_value());
  EXPECT_EQ(*code, 2);
  EXPECT_THAT(replica.Stdout() + replica.Stderr(), HasSubstr("share a PostgreSQL database"));
  EXPECT_FALSE(std::filesystem::exists(TempPath("fleet.db")));
}

}  // namespace
}  // namespace fleetnav
