// Durability: fleetnavd as a real process is killed with SIGKILL in the middle of a burst of
// SubmitJob calls and restarted on the same store (an SQLite file, or a PostgreSQL database). Every
// acknowledged job must be there, in a consistent state, and none twice.
#include <fcntl.h>
#include <gmock/gmock.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <atomic>
#include <fstream>
#include <map>
#include <set>
#include <thread>

#include "fleet_fixture.hpp"
#include "postgres_server.hpp"

extern char** environ;

namespace fleetnav {
namespace {

/// fleetnavd in a child process on an ephemeral port.
class ServerProcess {
 public:
  explicit ServerProcess(const std::string& db_path) {
    port_file_ = testing::UniqueTempPath("port");
    std::vector<std::string> args = {FLEETNAV_FLEETNAVD_PATH, "--insecure", "--listen",
                                     "127.0.0.1:0",           "--db",       db_path,
                                     "--port-file",           port_file_};
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
    EXPECT_EQ(posix_spawn(&pid_, argv[0], &actions, nullptr, argv.data(), environ), 0);
    posix_spawn_file_actions_destroy(&actions);
    for (int i = 0; i < 200 && port_ == 0; ++i) {
      std::ifstream in(port_file_);
      in >> port_;
      if (port_ == 0) std::this_thread::sleep_for(std::chrono::milliseconds(25));
    }
  }
  ~ServerProcess() {
    if (pid_ > 0) Kill(SIGTERM);
    std::remove(port_file_.c_str());
  }
  void Kill(int signal) {
    kill(pid_, signal);
    int status = 0;
    waitpid(pid_, &status, 0);
    pid_ = -1;
  }
  int port() const { return port_; }

 private:
  pid_t pid_ = -1;
  int port_ = 0;
  std::string port_file_;
};

std::unique_ptr<v1::FleetService::Stub> StubFor(int port) {
  return v1::FleetService::NewStub(
      grpc::CreateChannel("127.0.0.1:" + std::to_string(port), grpc::InsecureChannelCredentials()));
}

/// The store fleetnavd runs on: an SQLite file or a database of a real PostgreSQL server.
class CrashRecoveryTest : public ::testing::TestWithParam<std::string> {
 protected:
  /// A fresh `--db` value of the test's engine.
  static std::string NewStore() {
    if (GetParam() == "Sqlite") return testing::UniqueTempPath("crash") + ".db";
    absl::StatusOr<std::string> uri = testing::NewSharedDatabase("crash");
    EXPECT_TRUE(uri.ok()) << uri.status();
    return uri.value_or("");
  }
};

TEST_P(CrashRecoveryTest, EveryAcknowledgedJobSurvivesKillDashNineExactlyOnce) {
  const std::string db_path = NewStore();
  std::map<std::string, std::string> acknowledged;  // idempotency key -> job id
  {
    ServerProcess server(db_path);
    ASSERT_GT(server.port(), 0) << "fleetnavd did not start";
    auto fleet = StubFor(server.port());
    // A map and a route to submit jobs for.
    absl::StatusOr<OccupancyGrid> grid = OccupancyGrid::Filled(40, 40, 0.1, Pose2(), 0);
    grpc::ClientContext map_context;
    v1::PutMapRequest map;
    map.set_map_id("barn");
    *map.mutable_grid() = ToProto(*grid);
    v1::PutMapResponse map_response;
    ASSERT_TRUE(fleet->PutMap(&map_context, map, &map_response).ok());
    grpc::ClientContext route_context;
    v1::PutRouteRequest route;
    *route.mutable_route() = ToProto(testing::FleetServerFixture::StraightRoute("alley", 1.0));
    v1::PutRouteResponse route_response;
    ASSERT_TRUE(fleet->PutRoute(&route_context, route, &route_response).ok());

    // Two submitters until the kill; each remembers what the server acknowledged.
    std::atomic<bool> stop{false};
    std::mutex mutex;
    std::atomic<int> sent{0};
    auto submitter = [&](int id) {
      for (int i = 0; !stop.load(); ++i) {
        const std::string key = "s" + std::to_string(id) + "-" + std::to_string(i);
        grpc::ClientContext context;
        context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(2));
        v1::SubmitJobRequest request;
        request.set_route_name("alley");
        request.set_idempotency_key(key);
        v1::SubmitJobResponse response;
        sent.fetch_add(1);
        if (!fleet->SubmitJob(&context, request, &response).ok()) return;
        std::lock_guard<std::mutex> lock(mutex);
        acknowledged[key] = response.job().job_id();
      }
    };
    std::thread a(submitter, 0), b(submitter, 1);
    while (sent.load() < 150) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    server.Kill(SIGKILL);
    stop.store(true);
    a.join();
    b.join();
  }
  ASSERT_GE(acknowledged.size(), 100u);

  ServerProcess restarted(db_path);
  ASSERT_GT(restarted.port(), 0) << "fleetnavd did not restart";
  auto fleet = StubFor(restarted.port());
  std::vector<v1::Job> jobs;
  std::string token;
  do {
    grpc::ClientContext context;
    v1::ListJobsRequest request;
    request.set_page_size(1000);
    request.set_page_token(token);
    v1::ListJobsResponse page;
    ASSERT_TRUE(fleet->ListJobs(&context, request, &page).ok());
    jobs.insert(jobs.end(), page.jobs().begin(), page.jobs().end());
    token = page.next_page_token();
  } while (!token.empty());

  // Every stored job, not a sample: once, queued, with its first event, and one that a
  // submitter sent (acknowledged or not: the kill may fall between commit and reply).
  std::map<std::string, std::string> keys;  // idempotency key -> stored job id
  std::set<std::string> ids;
  for (const v1::Job& job : jobs) {
    EXPECT_TRUE(keys.emplace(job.idempotency_key(), job.job_id()).second)
        << "twice: " << job.idempotency_key();
    EXPECT_EQ(job.idempotency_key().rfind('s', 0), 0u) << "never sent: " << job.idempotency_key();
    EXPECT_TRUE(ids.insert(job.job_id()).second);
    EXPECT_EQ(job.state(), v1::JOB_STATE_QUEUED);  // nothing could have run it
    // Every stored job has its first event, stored in the same transaction.
    grpc::ClientContext watch_context;
    watch_context.set_deadline(std::chrono::system_clock::now() + std::chrono::milliseconds(300));
    v1::WatchJobRequest watch;
    watch.set_job_id(job.job_id());
    auto reader = fleet->WatchJob(&watch_context, watch);
    v1::JobEvent first;
    ASSERT_TRUE(reader->Read(&first));
    EXPECT_EQ(first.type(), v1::JOB_EVENT_TYPE_QUEUED);
    watch_context.TryCancel();
    (void)reader->Finish();
  }
  EXPECT_GE(jobs.size(), acknowledged.size());
  for (const auto& [key, job_id] : acknowledged) {
    auto stored = keys.find(key);
    ASSERT_NE(stored, keys.end()) << "acknowledged job lost: " << key << " (" << job_id << ")";
    EXPECT_EQ(stored->second, job_id) << key << " acknowledged as one job, stored as another";
  }
  if (GetParam() == "Sqlite") std::remove(db_path.c_str());
}

/// One SubmitJob with an idempotency key.
grpc::Status Submit(v1::FleetService::Stub& fleet, const std::string& key) {
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(5));
  v1::SubmitJobRequest request;
  request.set_route_name("alley");
  request.set_idempotency_key(key);
  v1::SubmitJobResponse response;
  return fleet.SubmitJob(&context, request, &response);
}

TEST(PostgresOutageTest, FleetnavdSaysUnavailableWhileTheDatabaseIsGoneAndGoesOnAfter) {
  absl::StatusOr<std::unique_ptr<testing::TemporaryPostgres>> postgres =
      testing::TemporaryPostgres::Start();
  ASSERT_TRUE(postgres.ok()) << postgres.status();
  absl::StatusOr<std::string> uri = (*postgres)->CreateDatabase("fleet");
  ASSERT_TRUE(uri.ok()) << uri.status();
  server::FleetServerParams params;
  params.listen_address = "127.0.0.1:0";
  params.db_path = *uri;
  params.postgres.reconnect_wait_s = 0.3;
  server::FleetServer server(params);
  absl::StatusOr<int> port = server.Start();
  ASSERT_TRUE(port.ok()) << port.status();
  EXPECT_THAT(server.store_description(), ::testing::HasSubstr("PostgreSQL database fleet"));
  auto fleet = StubFor(*port);
  grpc::ClientContext route_context;
  v1::PutRouteRequest route;
  absl::StatusOr<OccupancyGrid> grid = OccupancyGrid::Filled(40, 40, 0.1, Pose2(), 0);
  ASSERT_TRUE(server.app().maps().Put("barn", *grid, "").ok());
  *route.mutable_route() = ToProto(testing::FleetServerFixture::StraightRoute("alley", 1.0));
  v1::PutRouteResponse route_response;
  ASSERT_TRUE(fleet->PutRoute(&route_context, route, &route_response).ok());
  ASSERT_TRUE(Submit(*fleet, "before").ok());

  ASSERT_TRUE((*postgres)->Kill().ok());
  const grpc::Status during = Submit(*fleet, "during");
  EXPECT_EQ(during.error_code(), grpc::StatusCode::UNAVAILABLE) << during.error_message();
  ASSERT_TRUE((*postgres)->Restart().ok());
  // The first call after reconnects; the server never needed a restart.
  ASSERT_TRUE(Submit(*fleet, "after").ok());
  absl::StatusOr<storage::JobPage> jobs = server.app().jobs().List({});
  ASSERT_TRUE(jobs.ok()) << jobs.status();
  std::set<std::string> keys;
  for (const Job& job : jobs->jobs) keys.insert(job.idempotency_key);
  EXPECT_EQ(keys, (std::set<std::string>{"before", "after"}));  // nothing of "during"
  server.Shutdown();
}

INSTANTIATE_TEST_SUITE_P(Stores, CrashRecoveryTest, ::testing::Values("Sqlite", "Postgres"),
                         [](const auto& info) { return info.param; });

}  // namespace
}  // namespace fleetnav
