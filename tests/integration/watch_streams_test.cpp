// Watch streams and the robot table's housekeeping over real loopback gRPC: many open watchers
// hold no thread each and are woken by changes; an offline robot can be forgotten, and one that
// stays away is evicted, both also told to fleet watchers.
#include <dirent.h>
#include <gmock/gmock.h>

#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "fleet_fixture.hpp"
#include "fleetnav/proto/telemetry_convert.hpp"
#include "fleetnav/v1/agent_service.grpc.pb.h"

namespace fleetnav {
namespace {

using AgentStream = grpc::ClientReaderWriter<v1::AgentMessage, v1::ServerMessage>;

int ThreadCount() {
  int count = 0;
  if (DIR* dir = opendir("/proc/self/task")) {
    while (dirent* entry = readdir(dir)) count += entry->d_name[0] != '.';
    closedir(dir);
  }
  return count;
}

class WatchStreamsTest : public testing::FleetServerFixture {
 protected:
  server::FleetServerParams Params() override {
    server::FleetServerParams params = FleetServerFixture::Params();
    params.jobs.evict_offline_robots_after_s = evict_after_s_;
    return params;
  }

  /// A robot's stream: hello, then the welcome read.
  std::unique_ptr<AgentStream> Connect(const std::string& robot_id, grpc::ClientContext* context) {
    auto agents = v1::AgentService::NewStub(channel_);
    std::unique_ptr<AgentStream> stream = agents->Connect(context);
    v1::AgentMessage hello;
    *hello.mutable_hello() = ToProto(RobotIdentity{robot_id, LelyVectorModel(), {"straight"}, "t"});
    EXPECT_TRUE(stream->Write(hello));
    v1::ServerMessage welcome;
    EXPECT_TRUE(stream->Read(&welcome));
    return stream;
  }

  grpc::Status Forget(const std::string& robot_id) {
    grpc::ClientContext context;
    v1::ForgetRobotRequest request;
    request.set_robot_id(robot_id);
    v1::ForgetRobotResponse response;
    return fleet_->ForgetRobot(&context, request, &response);
  }

  int RobotCount() {
    grpc::ClientContext context;
    v1::ListRobotsResponse robots;
    EXPECT_TRUE(fleet_->ListRobots(&context, v1::ListRobotsRequest(), &robots).ok());
    return robots.robots_size();
  }

  double evict_after_s_ = 0.0;  // never
};

TEST_F(WatchStreamsTest, HundredsOfWatchersHoldNoThreadEachAndAllHearTheJobEnd) {
  PutBarn();
  ASSERT_TRUE(PutRoute(StraightRoute("long", 8.0)).ok());
  v1::SubmitJobResponse submitted;
  ASSERT_TRUE(Submit("long", "", &submitted).ok());
  const std::string job_id = submitted.job().job_id();
  const int threads_before = ThreadCount();

  constexpr int kEach = 150;
  struct Stream {
    grpc::ClientContext context;
    std::unique_ptr<grpc::ClientReader<v1::JobEvent>> jobs;
    std::unique_ptr<grpc::ClientReader<v1::FleetUpdate>> fleet;
  };
  std::vector<std::unique_ptr<Stream>> streams;
  for (int i = 0; i < kEach; ++i) {
    auto job_stream = std::make_unique<Stream>();
    v1::WatchJobRequest watch_job;
    watch_job.set_job_id(job_id);
    job_stream->jobs = fleet_->WatchJob(&job_stream->context, watch_job);
    v1::JobEvent queued;
    ASSERT_TRUE(job_stream->jobs->Read(&queued));
    EXPECT_EQ(queued.type(), v1::JOB_EVENT_TYPE_QUEUED);
    streams.push_back(std::move(job_stream));

    auto fleet_stream = std::make_unique<Stream>();
    fleet_stream->fleet = fleet_->WatchFleet(&fleet_stream->context, v1::WatchFleetRequest());
    v1::FleetUpdate snapshot;
    ASSERT_TRUE(fleet_stream->fleet->Read(&snapshot));
    EXPECT_TRUE(snapshot.snapshot());
    streams.push_back(std::move(fleet_stream));
  }
  // Served with a thread each, 300 open streams would add about 300 threads to this process.
  EXPECT_LT(ThreadCount() - threads_before, 30);

  // Unary calls are answered while they are open, and a change reaches every job watcher.
  grpc::ClientContext cancel_context;
  v1::CancelJobRequest cancel;
  cancel.set_job_id(job_id);
  v1::CancelJobResponse cancelled;
  ASSERT_TRUE(fleet_->CancelJob(&cancel_context, cancel, &cancelled).ok());
  int ended = 0;
  for (auto& stream : streams) {
    if (!stream->jobs) continue;
    v1::JobEvent event;
    do {  // the dispatcher may have said why the job waits (QUEUED with a reason) before
      ASSERT_TRUE(stream->jobs->Read(&event));
    } while (event.type() == v1::JOB_EVENT_TYPE_QUEUED);
    EXPECT_EQ(event.type(), v1::JOB_EVENT_TYPE_CANCELLED);
    EXPECT_FALSE(stream->jobs->Read(&event));  // the stream ends with the job
    EXPECT_TRUE(stream->jobs->Finish().ok());
    ++ended;
  }
  EXPECT_EQ(ended, kEach);

  // A robot connecting reaches every fleet watcher.
  grpc::ClientContext agent_context;
  std::unique_ptr<AgentStream> agent = Connect("ra", &agent_context);
  for (auto& stream : streams) {
    if (!stream->fleet) continue;
    v1::FleetUpdate update;
    ASSERT_TRUE(stream->fleet->Read(&update));
    ASSERT_EQ(update.robots_size(), 1);
    EXPECT_EQ(update.robots(0).robot_id(), "ra");
    stream->context.TryCancel();
    (void)stream->fleet->Finish();
  }
  agent->WritesDone();
  (void)agent->Finish();
}

TEST_F(WatchStreamsTest, AnOfflineRobotCanBeForgottenAndWatchersAreTold) {
  EXPECT_EQ(Forget("nobody").error_code(), grpc::StatusCode::NOT_FOUND);
  grpc::ClientContext agent_context;
  std::unique_ptr<AgentStream> agent = Connect("ra", &agent_context);
  const grpc::Status online = Forget("ra");
  EXPECT_EQ(online.error_code(), grpc::StatusCode::FAILED_PRECONDITION);
  EXPECT_THAT(online.error_message(), ::testing::HasSubstr("connected"));

  grpc::ClientContext watch_context;
  auto watch = fleet_->WatchFleet(&watch_context, v1::WatchFleetRequest());
  v1::FleetUpdate update;
  ASSERT_TRUE(watch->Read(&update));
  ASSERT_EQ(update.robots_size(), 1);

  agent->WritesDone();
  (void)agent->Finish();
  for (int i = 0;
       i < 100 && server_->app().registry().Get("ra")->connection != ConnectionState::kOffline;
       ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_TRUE(Forget("ra").ok());
  EXPECT_EQ(RobotCount(), 0);
  bool told = false;
  for (int i = 0; i < 5 && !told; ++i) {
    ASSERT_TRUE(watch->Read(&update));
    for (const std::string& id : update.removed_robot_ids()) told |= id == "ra";
  }
  EXPECT_TRUE(told);
  watch_context.TryCancel();
  (void)watch->Finish();

  // Forgotten in the store too: it does not come back with a restart.
  StopServer();
  StartServer();
  EXPECT_EQ(RobotCount(), 0);
}

class EvictionTest : public WatchStreamsTest {
 protected:
  void SetUp() override {
    evict_after_s_ = 0.3;
    WatchStreamsTest::SetUp();
  }
};

TEST_F(EvictionTest, ARobotOfflineLongerThanTheEvictionTimeIsForgotten) {
  {
    grpc::ClientContext context;
    std::unique_ptr<AgentStream> agent = Connect("ra", &context);
    EXPECT_EQ(RobotCount(), 1);
    agent->WritesDone();
    (void)agent->Finish();
  }
  int count = 1;
  for (int i = 0; i < 200 && count != 0; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    count = RobotCount();
  }
  EXPECT_EQ(count, 0);
  StopServer();
  StartServer();
  EXPECT_EQ(RobotCount(), 0);
}

}  // namespace
}  // namespace fleetnav
