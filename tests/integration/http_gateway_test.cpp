// fleetnavd's HTTP port over real loopback HTTP: the dashboard's page and API, the pushed state,
// the pause button reaching the robot's stream, /metrics, and what it refuses.
#include "fleetnav/server/http/http_gateway.hpp"

#include <gmock/gmock.h>

#include <nlohmann/json.hpp>

#include "fleet_fixture.hpp"
#include "fleetnav/proto/telemetry_convert.hpp"
#include "fleetnav/v1/agent_service.grpc.pb.h"
// Last: httplib.h includes <resolv.h>, whose `_res` macro breaks Eigen's headers.
#include <httplib.h>

namespace fleetnav {
namespace {

using ::testing::HasSubstr;
using AgentStream = grpc::ClientReaderWriter<v1::AgentMessage, v1::ServerMessage>;

class HttpGatewayTest : public testing::FleetServerFixture {
 protected:
  void SetUp() override {
    FleetServerFixture::SetUp();
    server::http::HttpGatewayParams params;
    params.listen_address = "127.0.0.1:0";
    gateway_ = std::make_unique<server::http::HttpGateway>(
        &server_->app(), [this] { return server_->RenderMetrics(); }, params);
    absl::StatusOr<int> port = gateway_->Start();
    ASSERT_TRUE(port.ok()) << port.status();
    http_ = std::make_unique<httplib::Client>("127.0.0.1", *port);
    http_->set_read_timeout(5, 0);
  }
  void TearDown() override {
    gateway_->Stop();
    FleetServerFixture::TearDown();
  }

  nlohmann::json GetJson(const std::string& path) {
    httplib::Result result = http_->Get(path);
    EXPECT_TRUE(result) << path;
    if (!result) return {};
    EXPECT_EQ(result->status, 200) << path << ": " << result->body;
    return nlohmann::json::parse(result->body);
  }

  /// A robot "lely1" on an agent stream that has been assigned `job_id`.
  std::unique_ptr<AgentStream> RobotWithJob(grpc::ClientContext* context, std::string* job_id) {
    PutBarn();
    EXPECT_TRUE(PutRoute(StraightRoute("alley", 5.0)).ok());
    v1::SubmitJobResponse submitted;
    EXPECT_TRUE(Submit("alley", "", &submitted).ok());
    *job_id = submitted.job().job_id();
    agents_ = v1::AgentService::NewStub(channel_);
    std::unique_ptr<AgentStream> agent = agents_->Connect(context);
    v1::AgentMessage hello;
    *hello.mutable_hello() = ToProto(RobotIdentity{"lely1", LelyVectorModel(), {"straight"}, "t"});
    EXPECT_TRUE(agent->Write(hello));
    v1::ServerMessage message;
    EXPECT_TRUE(agent->Read(&message));  // welcome
    EXPECT_TRUE(agent->Read(&message));
    EXPECT_EQ(message.assignment().job().job_id(), *job_id);
    Telemetry telemetry;
    telemetry.stamp_ns = 1;
    telemetry.pose_in_map = Pose2(-5.5, 0.25, 0.0);
    telemetry.battery_fraction = 0.75;
    telemetry.job_id = *job_id;
    v1::AgentMessage report;
    *report.mutable_telemetry() = ToProto(telemetry);
    EXPECT_TRUE(agent->Write(report));
    return agent;
  }

  std::unique_ptr<server::http::HttpGateway> gateway_;
  std::unique_ptr<httplib::Client> http_;
  std::unique_ptr<v1::AgentService::Stub> agents_;
};

TEST_F(HttpGatewayTest, TheStateShowsTheServersRobotsAndJobs) {
  grpc::ClientContext context;
  std::string job_id;
  std::unique_ptr<AgentStream> agent = RobotWithJob(&context, &job_id);
  nlohmann::json state;
  for (int i = 0; i < 200; ++i) {  // the telemetry lands asynchronously
    state = GetJson("/api/state");
    if (!state["robots"].empty() && state["robots"][0].contains("pose")) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_EQ(state["robots"].size(), 1u);
  EXPECT_EQ(state["robots"][0]["robot_id"], "lely1");
  EXPECT_EQ(state["robots"][0]["connection"], "online");
  EXPECT_NEAR(state["robots"][0]["pose"]["x_m"].get<double>(), -5.5, 1e-9);
  EXPECT_NEAR(state["robots"][0]["battery"].get<double>(), 0.75, 1e-9);
  ASSERT_EQ(state["jobs"].size(), 1u);
  EXPECT_EQ(state["jobs"][0]["job_id"], job_id);
  EXPECT_EQ(state["jobs"][0]["robot_id"], "lely1");

  const nlohmann::json map = GetJson("/api/maps/barn");
  EXPECT_GT(map["width"].get<int>(), 0);
  EXPECT_FALSE(map["site"]["markers"].empty());
  EXPECT_EQ(map["site"]["routes"][0]["name"], "alley");
  EXPECT_EQ(GetJson("/api/maps")[0]["map_id"], "barn");
  EXPECT_EQ(GetJson("/api/jobs/" + job_id + "/events")[0]["type"], "JOB_EVENT_TYPE_QUEUED");
  agent->WritesDone();
  context.TryCancel();
}

TEST_F(HttpGatewayTest, ThePauseButtonStopsTheRobotThroughItsStream) {
  grpc::ClientContext context;
  std::string job_id;
  std::unique_ptr<AgentStream> agent = RobotWithJob(&context, &job_id);
  httplib::Result paused = http_->Post("/api/jobs/" + job_id + "/pause", "", "text/plain");
  ASSERT_TRUE(paused);
  ASSERT_EQ(paused->status, 200) << paused->body;
  EXPECT_EQ(nlohmann::json::parse(paused->body)["state"], "paused");
  v1::ServerMessage message;
  do {
    ASSERT_TRUE(agent->Read(&message));
  } while (!message.has_command());
  EXPECT_EQ(message.command().type(), v1::Command::TYPE_PAUSE);
  EXPECT_EQ(message.command().reason(), "paused from the dashboard");
  // Twice is a conflict, said in JSON; an unknown job is 404.
  httplib::Result again = http_->Post("/api/jobs/" + job_id + "/pause", "", "text/plain");
  EXPECT_EQ(again->status, 409);
  EXPECT_THAT(nlohmann::json::parse(again->body)["error"].get<std::string>(), HasSubstr("paused"));
  EXPECT_EQ(http_->Post("/api/jobs/job-999999/cancel", "", "text/plain")->status, 404);
  httplib::Result resumed = http_->Post("/api/jobs/" + job_id + "/resume", "", "text/plain");
  EXPECT_EQ(nlohmann::json::parse(resumed->body)["state"], "running");
  agent->WritesDone();
  context.TryCancel();
}

TEST_F(HttpGatewayTest, StateIsPushedAsServerSentEvents) {
  PutBarn();
  std::string received;
  int events = 0;
  httplib::Result result = http_->Get("/api/events", [&](const char* data, size_t length) {
    received.append(data, length);
    for (size_t at = 0; (at = received.find("event: state\n", at)) != std::string::npos; ++at) {
      ++events;
      received.erase(0, at + 1);
      at = 0;
    }
    return events < 3;  // stop after three pushes
  });
  EXPECT_GE(events, 3);
}

TEST_F(HttpGatewayTest, MetricsCountRpcsRobotsAndJobs) {
  PutBarn();
  ASSERT_TRUE(PutRoute(StraightRoute("alley", 5.0)).ok());
  v1::SubmitJobResponse submitted;
  ASSERT_TRUE(Submit("alley", "", &submitted).ok());
  grpc::ClientContext context;
  v1::GetJobRequest missing;
  missing.set_job_id("job-999999");
  v1::GetJobResponse response;
  ASSERT_FALSE(fleet_->GetJob(&context, missing, &response).ok());
  httplib::Result metrics = http_->Get("/metrics");
  ASSERT_TRUE(metrics);
  EXPECT_EQ(metrics->status, 200);
  const std::string& text = metrics->body;
  EXPECT_THAT(
      text,
      HasSubstr(
          R"(fleetnav_rpcs_total{code="OK",method="/fleetnav.v1.FleetService/SubmitJob"} 1)"));
  EXPECT_THAT(
      text,
      HasSubstr(
          R"(fleetnav_rpcs_total{code="NOT_FOUND",method="/fleetnav.v1.FleetService/GetJob"} 1)"));
  EXPECT_THAT(text, HasSubstr(R"(fleetnav_jobs{state="queued"} 1)"));
  EXPECT_THAT(text, HasSubstr(R"(fleetnav_robots{state="online"} 0)"));
  EXPECT_THAT(text, HasSubstr("fleetnav_store_transaction_duration_seconds_count"));
  EXPECT_THAT(text, HasSubstr("# TYPE fleetnav_rpc_duration_seconds histogram"));
}

TEST_F(HttpGatewayTest, UnknownPathsTraversalAndOversizedRequestsAreRefused) {
  EXPECT_EQ(http_->Get("/")->status, 200);
  EXPECT_THAT(http_->Get("/")->body, HasSubstr("<title>fleetnav dashboard</title>"));
  EXPECT_THAT(http_->Get("/app.js")->get_header_value("Content-Type"), HasSubstr("javascript"));
  for (const char* path : {"/../../etc/passwd", "/%2e%2e/%2e%2e/etc/passwd", "/assets/../main.cpp",
                           "/index.html/..", "/api/maps/..%2f..%2fetc", "/nothing"}) {
    httplib::Result result = http_->Get(path);
    ASSERT_TRUE(result) << path;
    EXPECT_GE(result->status, 400) << path;
    EXPECT_THAT(result->body, ::testing::Not(HasSubstr("root:"))) << path;
  }
  const std::string big(200 * 1024, 'x');
  httplib::Result oversized = http_->Post("/api/jobs/job-000001/pause", big, "text/plain");
  ASSERT_TRUE(oversized);
  EXPECT_EQ(oversized->status, 413);
  EXPECT_EQ(http_->Get("/healthz")->status, 200);  // still serving
}

}  // namespace
}  // namespace fleetnav
