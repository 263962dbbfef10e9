// fleetnavd replicas serving TLS with one development PKI, run as processes: a robot's
// certificate verified by a follower reaches the leader as its robot id (and cannot speak for
// another robot, not even by sending the relay's own headers); tokens, also those made at run
// time, are checked by the leader for calls through any replica; the leader port refuses forged
// relays; every replica serves the dashboard and /metrics over HTTPS; after the leader is killed
// the survivor leads and its robots and dashboard come back through it.
#include <gmock/gmock.h>
#include <grpcpp/create_channel.h>
#include <grpcpp/generic/generic_stub.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/strip.h"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/proto/channel_credentials.hpp"
#include "fleetnav/proto/telemetry_convert.hpp"
#include "fleetnav/scenario/child_process.hpp"
#include "fleetnav/v1/access_service.grpc.pb.h"
#include "fleetnav/v1/agent_service.grpc.pb.h"
#include "fleetnav/v1/fleet_service.grpc.pb.h"
#include "postgres_server.hpp"
#include "testing/eventually.hpp"
// Last: httplib.h includes <resolv.h>, whose `_res` macro breaks Eigen's headers.
#include <httplib.h>

namespace fleetnav {
namespace {

using fleetnav::testing::Eventually;
using scenario::ChildProcess;
using ::testing::HasSubstr;
using Metadata = std::vector<std::pair<std::string, std::string>>;

constexpr char kListRobots[] = "/fleetnav.v1.FleetService/ListRobots";

/// An HTTP answer's status, or -1 when there was none.
int StatusOf(const httplib::Result& result) { return result ? result->status : -1; }

std::string TempPath(const std::string& name) {
  return (std::filesystem::path(::testing::TempDir()) /
          absl::StrCat("replica-tls-", getpid(), "-", name))
      .string();
}

class ReplicaTlsTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    pki_dir = new std::string(TempPath("pki"));
    const std::string command =
        absl::StrCat(FLEETNAV_DEV_CERTS_SCRIPT, " ", *pki_dir, " lely1 lely2 >/dev/null");
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
  }
  static void TearDownTestSuite() {
    std::filesystem::remove_all(*pki_dir);
    delete pki_dir;
  }

  static std::string Pki(const std::string& name) { return *pki_dir + "/" + name; }
  static std::string Bearer(const std::string& role) {
    return "Bearer " +
           std::string(absl::StripAsciiWhitespace(scenario::ReadWholeFile(Pki(role + ".token"))));
  }

  /// Starts replica `i` with the PKI's files and a dashboard; false when it did not start.
  bool Start(size_t i) {
    if (replicas_.size() <= i) replicas_.resize(i + 1);
    Replica& replica = replicas_[i];
    ++replica.starts;
    const std::string port_file = TempPath(absl::StrCat(i, ".port"));
    const std::string http_port_file = TempPath(absl::StrCat(i, ".http-port"));
    std::filesystem::remove(port_file);
    std::filesystem::remove(http_port_file);
    replica.process = std::make_unique<ChildProcess>(
        std::vector<std::string>{FLEETNAV_FLEETNAVD_PATH,
                                 "--replica",
                                 "--db",
                                 db_uri_,
                                 "--listen",
                                 "127.0.0.1:0",
                                 "--port-file",
                                 port_file,
                                 "--http-listen",
                                 "127.0.0.1:0",
                                 "--http-port-file",
                                 http_port_file,
                                 "--tls-cert",
                                 Pki("server.crt"),
                                 "--tls-key",
                                 Pki("server.key"),
                                 "--tls-client-ca",
                                 Pki("robot-ca.crt"),
                                 "--tokens",
                                 Pki("tokens.yaml")},
        Log(i), TempPath(absl::StrCat(i, ".", replica.starts, ".err")));
    replica.port = scenario::WaitForPortFile(port_file);
    replica.http_port = scenario::WaitForPortFile(http_port_file, 1.0);
    return replica.port > 0 && replica.http_port > 0;
  }
  std::string Log(size_t i) const {
    return TempPath(absl::StrCat(i, ".", replicas_[i].starts, ".out"));
  }
  bool LogSays(size_t i, const std::string& text) const {
    return scenario::ReadWholeFile(Log(i)).find(text) != std::string::npos;
  }

  /// A TLS channel to `address` trusting the server CA, with a robot's certificate when set.
  static std::shared_ptr<grpc::Channel> ChannelTo(const std::string& address,
                                                  const std::string& robot = "") {
    ClientTlsFiles files;
    files.ca_path = Pki("server-ca.crt");
    if (!robot.empty()) {
      files.cert_path = Pki("robot-" + robot + ".crt");
      files.key_path = Pki("robot-" + robot + ".key");
    }
    absl::StatusOr<std::shared_ptr<grpc::ChannelCredentials>> credentials =
        MakeChannelCredentials(files);
    EXPECT_TRUE(credentials.ok()) << credentials.status();
    return grpc::CreateChannel(address, *credentials);
  }
  std::shared_ptr<grpc::Channel> Channel(size_t i, const std::string& robot = "") const {
    return ChannelTo(absl::StrCat("127.0.0.1:", replicas_[i].port), robot);
  }

  /// Calls `method` with an empty request, `authorization` (none when empty) and `extra`.
  static grpc::Status Call(const std::shared_ptr<grpc::Channel>& channel, const std::string& method,
                           const std::string& authorization, const Metadata& extra = {}) {
    grpc::GenericStub stub(channel);
    grpc::ClientContext context;
    context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(2));
    if (!authorization.empty()) context.AddMetadata("authorization", authorization);
    for (const auto& [key, value] : extra) context.AddMetadata(key, value);
    grpc::Slice empty_message("");
    grpc::ByteBuffer request(&empty_message, 1), response;
    std::promise<grpc::Status> done;
    stub.UnaryCall(&context, method, grpc::StubOptions(), &request, &response,
                   [&](grpc::Status status) { done.set_value(std::move(status)); });
    return done.get_future().get();
  }

  /// An agent stream that said hello as `robot_id`; open until destroyed.
  struct Agent {
    grpc::ClientContext context;
    std::unique_ptr<grpc::ClientReaderWriter<v1::AgentMessage, v1::ServerMessage>> stream;
    grpc::Status status;  ///< OK once welcomed, else how the stream ended
    ~Agent() { context.TryCancel(); }
  };
  static std::unique_ptr<Agent> Connect(const std::shared_ptr<grpc::Channel>& channel,
                                        const std::string& robot_id, const Metadata& extra = {}) {
    auto agent = std::make_unique<Agent>();
    for (const auto& [key, value] : extra) agent->context.AddMetadata(key, value);
    agent->stream = v1::AgentService::NewStub(channel)->Connect(&agent->context);
    v1::AgentMessage hello;
    *hello.mutable_hello() = ToProto(RobotIdentity{robot_id, LelyVectorModel(), {}, "test"});
    v1::ServerMessage reply;
    if (agent->stream->Write(hello) && agent->stream->Read(&reply) && reply.has_welcome()) {
      agent->status = grpc::Status::OK;
    } else {
      agent->status = agent->stream->Finish();
    }
    return agent;
  }

  /// Whether the leader, asked through replica `i`, has `robot_id` online.
  bool Online(size_t i, const std::string& robot_id) const {
    grpc::ClientContext context;
    context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(2));
    context.AddMetadata("authorization", Bearer("viewer"));
    v1::ListRobotsResponse robots;
    if (!v1::FleetService::NewStub(Channel(i))
             ->ListRobots(&context, v1::ListRobotsRequest{}, &robots)
             .ok()) {
      return false;
    }
    for (const v1::RobotState& robot : robots.robots()) {
      if (robot.robot_id() == robot_id) return robot.connection() == v1::CONNECTION_STATE_ONLINE;
    }
    return false;
  }

  /// An HTTPS client of replica `i`'s dashboard, trusting the server CA.
  std::unique_ptr<httplib::SSLClient> Https(size_t i) const {
    auto https = std::make_unique<httplib::SSLClient>("127.0.0.1", replicas_[i].http_port);
    https->set_ca_cert_path(Pki("server-ca.crt"));
    https->enable_server_certificate_verification(true);
    https->set_read_timeout(5, 0);
    return https;
  }

  static std::string* pki_dir;
  std::string db_uri_;
  struct Replica {
    std::unique_ptr<ChildProcess> process;
    int port = 0;
    int http_port = 0;
    int starts = 0;
  };
  std::vector<Replica> replicas_;
};

std::string* ReplicaTlsTest::pki_dir = nullptr;

TEST_F(ReplicaTlsTest, RobotsAndOperatorsKeepTheirIdentitiesThroughAnyReplica) {
  absl::StatusOr<std::string> uri = fleetnav::testing::NewSharedDatabase("tls");
  ASSERT_TRUE(uri.ok()) << uri.status();
  db_uri_ = *uri;
  ASSERT_TRUE(Start(0));
  ASSERT_TRUE(Eventually([&] { return LogSays(0, "leading at epoch 1"); }, 20.0));
  EXPECT_TRUE(LogSays(0, "TLS, robot certificates and operator tokens"));
  ASSERT_TRUE(Start(1));
  // The follower answers once it knows the leader; the leader checks the token.
  ASSERT_TRUE(
      Eventually([&] { return Call(Channel(1), kListRobots, Bearer("viewer")).ok(); }, 20.0));
  EXPECT_EQ(Call(Channel(1), kListRobots, "").error_code(), grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_EQ(Call(Channel(1), kListRobots, "Bearer wrong").error_code(),
            grpc::StatusCode::UNAUTHENTICATED);
  // An operator token through the follower runs jobs (the empty request is then found wanting,
  // not refused); a viewer's does not.
  const grpc::Status by_operator =
      Call(Channel(1), "/fleetnav.v1.FleetService/PauseJob", Bearer("operator"));
  EXPECT_NE(by_operator.error_code(), grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_NE(by_operator.error_code(), grpc::StatusCode::PERMISSION_DENIED);
  const grpc::Status by_viewer =
      Call(Channel(1), "/fleetnav.v1.FleetService/PauseJob", Bearer("viewer"));
  EXPECT_EQ(by_viewer.error_code(), grpc::StatusCode::PERMISSION_DENIED);
  EXPECT_THAT(by_viewer.error_message(), HasSubstr("needs operator"));

  // A robot through the follower: the id its certificate proved reaches the leader.
  std::unique_ptr<Agent> lely1 = Connect(Channel(1, "lely1"), "lely1");
  ASSERT_TRUE(lely1->status.ok()) << lely1->status.error_message();
  EXPECT_TRUE(Eventually([&] { return Online(0, "lely1") && Online(1, "lely1"); }, 10.0));
  // lely1's certificate cannot speak for lely2, not even with the relay's header of its own
  // (the follower drops it); no certificate is no robot.
  const std::unique_ptr<Agent> impostor = Connect(Channel(1, "lely1"), "lely2");
  EXPECT_EQ(impostor->status.error_code(), grpc::StatusCode::PERMISSION_DENIED);
  EXPECT_THAT(impostor->status.error_message(), HasSubstr("lely2"));
  const std::unique_ptr<Agent> forged =
      Connect(Channel(1, "lely1"), "lely2", {{"fleetnav-relayed-robot", "lely2"}});
  EXPECT_EQ(forged->status.error_code(), grpc::StatusCode::PERMISSION_DENIED);
  const std::unique_ptr<Agent> no_certificate =
      Connect(Channel(1), "lely2", {{"fleetnav-relayed-robot", "lely2"}});
  EXPECT_EQ(no_certificate->status.error_code(), grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_FALSE(Online(0, "lely2"));
  // Through the leader's own public port (relayed over TLS to its leader port) as well.
  std::unique_ptr<Agent> lely2 = Connect(Channel(0, "lely2"), "lely2");
  ASSERT_TRUE(lely2->status.ok()) << lely2->status.error_message();
  EXPECT_TRUE(Eventually([&] { return Online(1, "lely2"); }, 10.0));

  // The leader port takes relayed robot ids only with the replicas' relay key.
  const std::string log = scenario::ReadWholeFile(Log(0));
  const size_t at = log.find("relay to ");
  ASSERT_NE(at, std::string::npos) << log;
  const std::string leader_port = log.substr(at + 9, log.find_first_of(", \n", at + 9) - (at + 9));
  const std::shared_ptr<grpc::Channel> leader = ChannelTo(leader_port);
  EXPECT_EQ(Connect(leader, "lely2", {{"fleetnav-relayed-robot", "lely2"}})->status.error_code(),
            grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_EQ(
      Connect(leader, "lely2",
              {{"fleetnav-relayed-robot", "lely2"}, {"fleetnav-relay-key", std::string(64, '0')}})
          ->status.error_code(),
      grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_EQ(
      Call(leader, kListRobots, Bearer("viewer"), {{"fleetnav-relay-key", "guess"}}).error_code(),
      grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_TRUE(Eventually([&] { return LogSays(0, "relayed call"); }, 5.0));

  // A token made at run time through one replica works at once through the other.
  std::string night;
  {
    grpc::ClientContext context;
    context.AddMetadata("authorization", Bearer("admin"));
    v1::CreateTokenRequest request;
    request.set_name("night");
    request.set_role(v1::OPERATOR_ROLE_OPERATOR);
    v1::CreateTokenResponse made;
    const grpc::Status status =
        v1::AccessService::NewStub(Channel(1))->CreateToken(&context, request, &made);
    ASSERT_TRUE(status.ok()) << status.error_message();
    night = "Bearer " + made.token();
  }
  EXPECT_TRUE(Call(Channel(0), kListRobots, night).ok());

  // Every replica serves the dashboard and /metrics over HTTPS, tokens checked by the leader.
  for (size_t i : {0u, 1u}) {
    SCOPED_TRACE(i);
    const std::unique_ptr<httplib::SSLClient> https = Https(i);
    EXPECT_EQ(StatusOf(https->Get("/healthz")), 200);
    EXPECT_EQ(StatusOf(https->Get("/metrics")), 401);
    const httplib::Result metrics = https->Get("/metrics", {{"Authorization", Bearer("viewer")}});
    ASSERT_TRUE(metrics) << httplib::to_string(metrics.error());
    EXPECT_EQ(metrics->status, 200);
    EXPECT_THAT(metrics->body, HasSubstr("fleetnav_robots"));
    const httplib::Result state = https->Get("/api/state", {{"Authorization", night}});
    ASSERT_TRUE(state);
    EXPECT_EQ(state->status, 200);
    EXPECT_THAT(state->body, HasSubstr("lely1"));
    EXPECT_EQ(StatusOf(https->Post("/api/jobs/job-000001/pause",
                                   {{"Authorization", Bearer("viewer")}}, "", "text/plain")),
              403);
    EXPECT_EQ(StatusOf(https->Post("/api/jobs/job-000001/pause",
                                   {{"Authorization", Bearer("operator")}}, "", "text/plain")),
              404);
  }
  // The event stream comes through a follower as it is pushed.
  {
    std::string events;
    Https(1)->Get("/api/events", {{"Authorization", Bearer("viewer")}},
                  [&](const char* data, size_t length) {
                    events.append(data, length);
                    return events.find("event: state", events.find("event: state") + 1) ==
                           std::string::npos;  // two events, then enough
                  });
    EXPECT_THAT(events, HasSubstr("lely2"));
  }

  // The leader killed: replica 1 takes over and serves the robots, the tokens and the
  // dashboard itself, through its own TLS relays.
  replicas_[0].process->Stop(SIGKILL, 5.0);
  v1::ServerMessage message;
  while (lely1->stream->Read(&message)) {
  }
  std::unique_ptr<Agent> again;
  ASSERT_TRUE(Eventually(
      [&] {
        again = Connect(Channel(1, "lely1"), "lely1");
        return again->status.ok();
      },
      20.0));
  EXPECT_TRUE(LogSays(1, "leading at epoch 2"));
  EXPECT_TRUE(Eventually([&] { return Online(1, "lely1"); }, 10.0));
  EXPECT_TRUE(Call(Channel(1), kListRobots, night).ok());
  EXPECT_TRUE(Eventually(
      [&] {
        const httplib::Result metrics =
            Https(1)->Get("/metrics", {{"Authorization", Bearer("viewer")}});
        return metrics && metrics->status == 200;
      },
      10.0));
}

TEST_F(ReplicaTlsTest, BadTlsFilesStopAReplicaBeforeItServes) {
  ChildProcess replica({FLEETNAV_FLEETNAVD_PATH, "--replica", "--db",
                        "postgresql://nobody@127.0.0.1:1/none", "--listen", "127.0.0.1:0",
                        "--tls-cert", Pki("server.crt"), "--tls-key", Pki("robot-lely1.key"),
                        "--tls-client-ca", Pki("robot-ca.crt"), "--tokens", Pki("tokens.yaml")},
                       TempPath("bad.out"), TempPath("bad.err"));
  const std::optional<int> code = replica.Wait(30.0);
  ASSERT_TRUE(code.has_value());
  EXPECT_EQ(*code, 1);
  EXPECT_THAT(replica.Stdout() + replica.Stderr(), HasSubstr("is not the key of the certificate"));
}

}  // namespace
}  // namespace fleetnav
