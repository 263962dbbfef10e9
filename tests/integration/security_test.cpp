// fleetnavd with TLS, robot certificates and operator tokens, over real TLS on loopback: every
// RPC refuses missing, malformed and wrong credentials; a robot cannot speak for another; a
// certificate of a foreign CA does not get in; and the server keeps serving throughout.
#include <arpa/inet.h>
#include <gmock/gmock.h>
#include <google/protobuf/descriptor.h>
#include <grpcpp/create_channel.h>
#include <grpcpp/generic/generic_stub.h>
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <future>
#include <set>
#include <thread>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/strip.h"
#include "fleetnav/proto/channel_credentials.hpp"
#include "fleetnav/proto/telemetry_convert.hpp"
#include "fleetnav/scenario/child_process.hpp"
#include "fleetnav/server/http/http_gateway.hpp"
#include "fleetnav/server/rpc/fleet_server.hpp"
#include "fleetnav/v1/agent_service.grpc.pb.h"
#include "fleetnav/v1/fleet_service.grpc.pb.h"
#include "test_paths.hpp"
// Last: httplib.h includes <resolv.h>, whose `_res` macro breaks Eigen's headers.
#include <httplib.h>

namespace fleetnav {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

std::string ReadText(const std::string& path) {
  std::ifstream in(path);
  std::string text;
  std::getline(in, text);
  return text;
}

/// A development PKI made by deploy/certs/make-dev-certs, and a second one whose CA fleetnavd
/// does not know.
class SecurityTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    pki_dir = new std::string(testing::UniqueTempPath("pki"));
    foreign_dir = new std::string(testing::UniqueTempPath("foreign-pki"));
    for (const std::string* dir : {pki_dir, foreign_dir}) {
      const std::string command =
          absl::StrCat(FLEETNAV_DEV_CERTS_SCRIPT, " ", *dir, " lely1 lely2 >/dev/null");
      ASSERT_EQ(std::system(command.c_str()), 0) << command;
    }
  }
  static void TearDownTestSuite() {
    std::filesystem::remove_all(*pki_dir);
    std::filesystem::remove_all(*foreign_dir);
    delete pki_dir;
    delete foreign_dir;
  }

  void SetUp() override {
    db_path_ = testing::UniqueTempPath("secure") + ".db";
    StartServer("127.0.0.1:0");
  }
  /// Starts fleetnavd on `listen_address` over the test's database.
  void StartServer(const std::string& listen_address) {
    server::FleetServerParams params;
    params.listen_address = listen_address;
    params.db_path = db_path_;
    params.security = {Pki("server.crt"), Pki("server.key"), Pki("robot-ca.crt"),
                       Pki("tokens.yaml")};
    params.on_access_refused = [this](const std::string& why) {
      absl::MutexLock lock(&log_mutex_);
      refusal_log_.push_back(why);
    };
    server_ = std::make_unique<server::FleetServer>(params);
    absl::StatusOr<int> port = server_->Start();
    ASSERT_TRUE(port.ok()) << port.status();
    address_ = absl::StrCat("127.0.0.1:", *port);
  }
  struct CtlResult {
    int code = -1;
    std::string out;
    std::string err;
  };
  /// Runs fleetnavctl against the server with the server's CA.
  CtlResult RunCtl(std::vector<std::string> args) {
    args.insert(args.begin(), {FLEETNAV_FLEETNAVCTL_PATH, "--server", address_,
                               "--tls-ca=" + Pki("server-ca.crt")});
    const std::string base = testing::UniqueTempPath("ctl-tls");
    scenario::ChildProcess child(args, base + ".out", base + ".err");
    CtlResult result;
    result.code = child.Wait(30.0).value_or(-1);
    result.out = child.Stdout();
    result.err = child.Stderr();
    return result;
  }
  void TearDown() override {
    server_->Shutdown();
    server_.reset();
    std::filesystem::remove(db_path_);
  }

  static std::string Pki(const std::string& name) { return *pki_dir + "/" + name; }
  /// Whether at least `count` refusal lines with "TLS handshake from ipv4:127.0.0.1:" and
  /// `what` are logged within `seconds`.
  bool LoggedWithin(double seconds, const std::string& what, size_t count) {
    const auto give_up = std::chrono::steady_clock::now() +
                         std::chrono::milliseconds(static_cast<int64_t>(seconds * 1000));
    while (true) {
      {
        absl::MutexLock lock(&log_mutex_);
        const auto found =
            std::count_if(refusal_log_.begin(), refusal_log_.end(), [&](const std::string& line) {
              return absl::StrContains(line, "TLS handshake from ipv4:127.0.0.1:") &&
                     absl::StrContains(line, what);
            });
        if (static_cast<size_t>(found) >= count) return true;
      }
      if (std::chrono::steady_clock::now() > give_up) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }
  static std::string Token(const std::string& role) { return ReadText(Pki(role + ".token")); }

  /// A TLS channel trusting the server's CA, with a robot's certificate when `robot` is set.
  std::shared_ptr<grpc::Channel> Channel(const std::string& robot = "",
                                         const std::string& pki = *pki_dir) {
    ClientTlsFiles files;
    files.ca_path = Pki("server-ca.crt");
    if (!robot.empty()) {
      files.cert_path = pki + "/robot-" + robot + ".crt";
      files.key_path = pki + "/robot-" + robot + ".key";
    }
    absl::StatusOr<std::shared_ptr<grpc::ChannelCredentials>> credentials =
        MakeChannelCredentials(files);
    EXPECT_TRUE(credentials.ok()) << credentials.status();
    return grpc::CreateChannel(address_, *credentials);
  }

  /// Calls `method` with an empty request and `authorization` (none when empty).
  grpc::Status Call(const std::shared_ptr<grpc::Channel>& channel, const std::string& method,
                    const std::string& authorization) {
    grpc::GenericStub stub(channel);
    grpc::ClientContext context;
    // Refusals come at once; an admitted watch stream would run until the deadline.
    context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(1));
    if (!authorization.empty()) context.AddMetadata("authorization", authorization);
    grpc::Slice empty_message("");  // the encoding of a message with every field at its default
    grpc::ByteBuffer request(&empty_message, 1), response;
    std::promise<grpc::Status> done;
    stub.UnaryCall(&context, method, grpc::StubOptions(), &request, &response,
                   [&](grpc::Status status) { done.set_value(std::move(status)); });
    return done.get_future().get();
  }

  static v1::AgentMessage Hello(const std::string& robot_id) {
    v1::AgentMessage message;
    *message.mutable_hello() = ToProto(RobotIdentity{robot_id, LelyVectorModel(), {}, "test"});
    return message;
  }

  /// Opens an agent stream, says hello as `robot_id` and returns how the server answered: OK
  /// once welcomed, else the stream's status.
  grpc::Status ConnectAs(const std::shared_ptr<grpc::Channel>& channel,
                         const std::string& robot_id) {
    auto agents = v1::AgentService::NewStub(channel);
    grpc::ClientContext context;
    context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(5));
    auto stream = agents->Connect(&context);
    stream->Write(Hello(robot_id));
    v1::ServerMessage reply;
    if (stream->Read(&reply) && reply.has_welcome()) {
      context.TryCancel();
      return grpc::Status::OK;
    }
    return stream->Finish();
  }

  static std::string* pki_dir;
  static std::string* foreign_dir;
  std::string db_path_;
  std::string address_;
  std::unique_ptr<server::FleetServer> server_;
  absl::Mutex log_mutex_;
  std::vector<std::string> refusal_log_ ABSL_GUARDED_BY(log_mutex_);
};

std::string* SecurityTest::pki_dir = nullptr;
std::string* SecurityTest::foreign_dir = nullptr;

int RoleRank(const std::string& role) { return role == "viewer" ? 0 : role == "operator" ? 1 : 2; }

/// The role each FleetService and AccessService method needs (docs/security.md); a method missing
/// here fails.
int NeededRank(const std::string& method) {
  static const std::set<std::string> kOperator = {"SubmitJob", "CancelJob",  "PauseJob",
                                                  "ResumeJob", "StopRobots", "ResumeRobots"};
  static const std::set<std::string> kAdmin = {
      "PutMap",   "DeleteMap",   "PutMarkerSet", "DeleteMarkerSet", "PutZones",   "DeleteZones",
      "PutRoute", "DeleteRoute", "ForgetRobot",  "CreateToken",     "ListTokens", "RevokeToken"};
  if (kAdmin.count(method) != 0) return 2;
  if (kOperator.count(method) != 0) return 1;
  return 0;
}

TEST_F(SecurityTest, EveryRpcRefusesMissingMalformedAndUnderprivilegedCredentials) {
  const std::shared_ptr<grpc::Channel> channel = Channel();
  int refused = 0, tried_refusals = 0, method_count = 0;
  for (const char* service_name : {"fleetnav.v1.FleetService", "fleetnav.v1.AccessService"}) {
    const google::protobuf::ServiceDescriptor* service =
        google::protobuf::DescriptorPool::generated_pool()->FindServiceByName(service_name);
    ASSERT_NE(service, nullptr) << service_name;
    method_count += service->method_count();
    for (int i = 0; i < service->method_count(); ++i) {
      const std::string name = service->method(i)->name();
      const std::string method = absl::StrCat("/", service_name, "/", name);
      SCOPED_TRACE(method);
      // No credentials, a malformed header, an unknown token: UNAUTHENTICATED, naming the
      // method.
      for (const std::string& authorization :
           {std::string(), std::string("Basic abc"), std::string("Bearer not-a-token"),
            std::string("Bearer ")}) {
        const grpc::Status status = Call(channel, method, authorization);
        ++tried_refusals;
        refused += status.error_code() == grpc::StatusCode::UNAUTHENTICATED;
        EXPECT_EQ(status.error_code(), grpc::StatusCode::UNAUTHENTICATED) << authorization;
        EXPECT_THAT(status.error_message(), HasSubstr(name));
      }
      // Each role: refused below the method's role, admitted at or above it (whatever the
      // empty request then makes of it).
      for (const std::string role : {"viewer", "operator", "admin"}) {
        const grpc::Status status = Call(channel, method, "Bearer " + Token(role));
        if (RoleRank(role) < NeededRank(name)) {
          ++tried_refusals;
          refused += status.error_code() == grpc::StatusCode::PERMISSION_DENIED;
          EXPECT_EQ(status.error_code(), grpc::StatusCode::PERMISSION_DENIED) << role;
          EXPECT_THAT(status.error_message(), HasSubstr("role " + role));
        } else {
          EXPECT_NE(status.error_code(), grpc::StatusCode::PERMISSION_DENIED) << role;
          EXPECT_NE(status.error_code(), grpc::StatusCode::UNAUTHENTICATED) << role;
        }
      }
    }
  }
  std::printf(
      "[ security ] %d FleetService and AccessService methods; %d of %d calls with missing, "
      "malformed, unknown or under-privileged credentials refused\n",
      method_count, refused, tried_refusals);
  EXPECT_EQ(refused, tried_refusals);
  const server::AccessCounts counts = server_->access_counts();
  EXPECT_EQ(counts.unauthenticated + counts.denied, static_cast<uint64_t>(tried_refusals));
  absl::MutexLock lock(&log_mutex_);
  EXPECT_EQ(refusal_log_.size(), static_cast<size_t>(tried_refusals));
}

TEST_F(SecurityTest, ARobotCertificateOpensOnlyItsOwnStreamAndTheSiteReads) {
  EXPECT_TRUE(ConnectAs(Channel("lely1"), "lely1").ok());
  // lely1's certificate cannot say hello as lely2.
  const grpc::Status impersonation = ConnectAs(Channel("lely1"), "lely2");
  EXPECT_EQ(impersonation.error_code(), grpc::StatusCode::PERMISSION_DENIED);
  EXPECT_THAT(impersonation.error_message(), HasSubstr("lely2"));
  // No certificate, only a token: no agent stream.
  const grpc::Status tokens_only = ConnectAs(Channel(), "lely1");
  EXPECT_EQ(tokens_only.error_code(), grpc::StatusCode::UNAUTHENTICATED);
  // A robot reads its site (a missing map is then "not found", not a refusal) but cannot
  // submit jobs or change the site.
  const std::shared_ptr<grpc::Channel> robot = Channel("lely2");
  EXPECT_EQ(Call(robot, "/fleetnav.v1.FleetService/ListMaps", "").error_code(),
            grpc::StatusCode::OK);
  EXPECT_EQ(Call(robot, "/fleetnav.v1.FleetService/SubmitJob", "").error_code(),
            grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_EQ(Call(robot, "/fleetnav.v1.FleetService/DeleteMap", "").error_code(),
            grpc::StatusCode::UNAUTHENTICATED);
  // Only lely1 ever registered.
  const std::vector<RobotRecord> robots = server_->app().registry().Snapshot();
  ASSERT_EQ(robots.size(), 1u);
  EXPECT_EQ(robots[0].identity.robot_id, "lely1");
}

TEST_F(SecurityTest, ACertificateOfAForeignCaDoesNotGetInAndTheServerKeepsServing) {
  const grpc::Status foreign = ConnectAs(Channel("lely1", *foreign_dir), "lely1");
  EXPECT_EQ(foreign.error_code(), grpc::StatusCode::UNAVAILABLE) << foreign.error_message();
  // A certificate of the right CA that has expired (made valid until yesterday).
  const std::string expired = testing::UniqueTempPath("expired");
  std::filesystem::create_directories(expired);
  const std::string make_expired = absl::StrCat(
      "cd ", expired, " && openssl req -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes ",
      "-subj /CN=lely1 -keyout robot-lely1.key -out lely1.csr 2>/dev/null && openssl x509 -req ",
      "-in lely1.csr -CA ", Pki("robot-ca.crt"), " -CAkey ", Pki("robot-ca.key"),
      " -CAcreateserial -days -1 -out robot-lely1.crt 2>/dev/null");
  ASSERT_EQ(std::system(make_expired.c_str()), 0);
  const grpc::Status stale = ConnectAs(Channel("lely1", expired), "lely1");
  EXPECT_EQ(stale.error_code(), grpc::StatusCode::UNAVAILABLE) << stale.error_message();
  std::filesystem::remove_all(expired);
  EXPECT_TRUE(server_->app().registry().Snapshot().empty());
  // A plaintext client gets nowhere either.
  auto plaintext = grpc::CreateChannel(address_, grpc::InsecureChannelCredentials());
  EXPECT_EQ(Call(plaintext, "/fleetnav.v1.FleetService/ListMaps", "Bearer " + Token("admin"))
                .error_code(),
            grpc::StatusCode::UNAVAILABLE);
  // The health service is open; the server still serves the right credentials.
  EXPECT_EQ(Call(Channel(), "/grpc.health.v1.Health/Check", "").error_code(), grpc::StatusCode::OK);
  EXPECT_EQ(Call(Channel(), "/fleetnav.v1.FleetService/ListMaps", "Bearer " + Token("viewer"))
                .error_code(),
            grpc::StatusCode::OK);
  EXPECT_TRUE(ConnectAs(Channel("lely1"), "lely1").ok());
  // Every refused handshake is a `refused:` line naming the peer, and counted.
  EXPECT_TRUE(LoggedWithin(5.0, "did not verify against the robot CA", 2));
  EXPECT_TRUE(LoggedWithin(5.0, "not TLS (a plaintext client?)", 1));
  EXPECT_GE(server_->access_counts().handshakes_refused, 3u);
}

TEST_F(SecurityTest, ARefusedHandshakeNamesItsPeer) {
  // A plaintext HTTP/2 client on a raw socket, whose own address is known.
  const int client = socket(AF_INET, SOCK_STREAM, 0);
  ASSERT_GE(client, 0);
  sockaddr_in server{};
  server.sin_family = AF_INET;
  server.sin_port =
      htons(static_cast<uint16_t>(std::stoi(address_.substr(address_.rfind(':') + 1))));
  inet_pton(AF_INET, "127.0.0.1", &server.sin_addr);
  ASSERT_EQ(connect(client, reinterpret_cast<sockaddr*>(&server), sizeof(server)), 0);
  sockaddr_in self{};
  socklen_t length = sizeof(self);
  getsockname(client, reinterpret_cast<sockaddr*>(&self), &length);
  const std::string preface = "PRI * HTTP/2.0\r\n\r\nSM\r\n\r\n";
  ASSERT_EQ(send(client, preface.data(), preface.size(), 0), static_cast<ssize_t>(preface.size()));
  char reply = 0;
  EXPECT_LE(recv(client, &reply, 1, 0), 0);  // closed without a word
  close(client);
  const std::string peer = absl::StrCat("ipv4:127.0.0.1:", ntohs(self.sin_port));
  EXPECT_TRUE(LoggedWithin(5.0, "TLS handshake from " + peer + ": not TLS", 1));
  EXPECT_EQ(server_->access_counts().handshakes_refused, 1u);
  // /metrics has the count.
  EXPECT_THAT(server_->RenderMetrics(), HasSubstr("fleetnav_tls_handshakes_refused_total 1"));
}

TEST_F(SecurityTest, FleetnavctlSpeaksTlsWithATokenAndSaysWhenItIsRefused) {
  const auto run = [&](std::vector<std::string> args) {
    args.insert(args.begin(), {FLEETNAV_FLEETNAVCTL_PATH, "--server", address_});
    const std::string base = testing::UniqueTempPath("ctl-tls");
    scenario::ChildProcess child(args, base + ".out", base + ".err");
    const int code = child.Wait(30.0).value_or(-1);
    return std::make_pair(code, child.Stderr());
  };
  const std::string ca = "--tls-ca=" + Pki("server-ca.crt");
  EXPECT_EQ(run({"robots", ca, "--token", Token("viewer")}).first, 0);
  const auto denied = run({"map", "delete", "--id", "barn", ca, "--token", Token("viewer")});
  EXPECT_EQ(denied.first, 6);
  EXPECT_THAT(denied.second, HasSubstr("needs admin"));
  EXPECT_EQ(run({"robots", ca}).first, 6);  // no token
  EXPECT_EQ(run({"robots", ca, "--token", "wrong"}).first, 6);
  // A plaintext fleetnavctl at a TLS server, and a wrong name: unavailable, with the TLS hint.
  const auto plaintext = run({"robots", "--timeout-s", "3"});
  EXPECT_EQ(plaintext.first, 5);
  EXPECT_THAT(plaintext.second, HasSubstr("serving TLS needs --tls-ca"));
  const auto wrong_name = run({"robots", ca, "--tls-server-name", "elsewhere", "--timeout-s", "3"});
  EXPECT_EQ(wrong_name.first, 5);
  EXPECT_THAT(wrong_name.second, HasSubstr("--tls-server-name"));
  // A missing CA file is a usage error, said before any call.
  const auto missing = run({"robots", "--tls-ca", Pki("nowhere.crt")});
  EXPECT_EQ(missing.first, 2);
  EXPECT_THAT(missing.second, HasSubstr("nowhere.crt"));
}

TEST_F(SecurityTest, TokensMadeAtRunTimeWorkAtOnceOutliveARestartAndRevokingIsImmediate) {
  // Only an admin manages tokens.
  const CtlResult by_operator =
      RunCtl({"tokens", "create", "night", "--role", "operator", "--token", Token("operator")});
  EXPECT_EQ(by_operator.code, 6) << by_operator.err;
  EXPECT_THAT(by_operator.err, HasSubstr("needs admin"));
  const CtlResult made =
      RunCtl({"tokens", "create", "night", "--role", "operator", "--token", Token("admin")});
  ASSERT_EQ(made.code, 0) << made.err;
  const std::string night(absl::StripTrailingAsciiWhitespace(made.out));
  ASSERT_EQ(night.size(), 64u) << made.out;
  EXPECT_THAT(made.err, HasSubstr("store it now"));
  // The new token works from the next call, with its role and no more.
  EXPECT_EQ(Call(Channel(), "/fleetnav.v1.FleetService/ListRobots", "Bearer " + night).error_code(),
            grpc::StatusCode::OK);
  EXPECT_EQ(Call(Channel(), "/fleetnav.v1.FleetService/DeleteMap", "Bearer " + night).error_code(),
            grpc::StatusCode::PERMISSION_DENIED);
  // A name in use, a bad name and a file token's name are refused and nothing is stored.
  EXPECT_EQ(
      RunCtl({"tokens", "create", "night", "--role", "viewer", "--token", Token("admin")}).code, 4);
  const CtlResult bad_name =
      RunCtl({"tokens", "create", "a b", "--role", "viewer", "--token", Token("admin")});
  EXPECT_EQ(bad_name.code, 4) << bad_name.err;
  EXPECT_THAT(bad_name.err, HasSubstr("token name"));
  EXPECT_EQ(
      RunCtl({"tokens", "create", "dev-admin", "--role", "admin", "--token", Token("admin")}).code,
      4);
  const CtlResult listed = RunCtl({"tokens", "--json", "--token", Token("admin")});
  ASSERT_EQ(listed.code, 0) << listed.err;
  EXPECT_THAT(listed.out, HasSubstr(R"({"created_unix_ms":0,"name":"dev-admin","role":"admin",)"
                                    R"("source":"file"})"));
  EXPECT_THAT(listed.out, HasSubstr(R"("name":"night","role":"operator","source":"store"})"));
  EXPECT_THAT(listed.out, Not(HasSubstr(night)));
  EXPECT_EQ(std::count(listed.out.begin(), listed.out.end(), '{'), 4);  // 3 file + night

  // A restart on the same database keeps the token.
  server_->Shutdown();
  server_.reset();
  StartServer(address_);
  EXPECT_EQ(Call(Channel(), "/fleetnav.v1.FleetService/ListRobots", "Bearer " + night).error_code(),
            grpc::StatusCode::OK);
  // Revoked: refused from the next call on, and after another restart too. The file's tokens
  // cannot be revoked at run time.
  const CtlResult file_revoke =
      RunCtl({"tokens", "revoke", "dev-viewer", "--token", Token("admin")});
  EXPECT_EQ(file_revoke.code, 4);
  EXPECT_THAT(file_revoke.err, HasSubstr("token file"));
  EXPECT_EQ(RunCtl({"tokens", "revoke", "ghost", "--token", Token("admin")}).code, 3);
  ASSERT_EQ(RunCtl({"tokens", "revoke", "night", "--token", Token("admin")}).code, 0);
  EXPECT_EQ(Call(Channel(), "/fleetnav.v1.FleetService/ListRobots", "Bearer " + night).error_code(),
            grpc::StatusCode::UNAUTHENTICATED);
  server_->Shutdown();
  server_.reset();
  StartServer(address_);
  EXPECT_EQ(Call(Channel(), "/fleetnav.v1.FleetService/ListRobots", "Bearer " + night).error_code(),
            grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_EQ(Call(Channel(), "/fleetnav.v1.FleetService/ListRobots", "Bearer " + Token("viewer"))
                .error_code(),
            grpc::StatusCode::OK);
}

TEST_F(SecurityTest, TheDashboardServesHttpsAndChecksTokensForReadsAndButtons) {
  server::http::HttpGatewayParams params;
  params.listen_address = "127.0.0.1:0";
  params.cert_path = Pki("server.crt");
  params.key_path = Pki("server.key");
  server::http::HttpGateway gateway(
      &server_->app(), [this] { return server_->RenderMetrics(); }, params);
  absl::StatusOr<int> port = gateway.Start();
  ASSERT_TRUE(port.ok()) << port.status();
  httplib::SSLClient https("localhost", *port);
  https.set_ca_cert_path(Pki("server-ca.crt").c_str());
  https.enable_server_certificate_verification(true);
  const auto bearer = [&](const std::string& role) {
    return httplib::Headers{{"Authorization", "Bearer " + Token(role)}};
  };
  EXPECT_EQ(https.Get("/healthz")->status, 200);
  EXPECT_EQ(https.Get("/")->status, 200);  // the page itself; it asks for a token
  EXPECT_EQ(https.Get("/api/state")->status, 401);
  EXPECT_EQ(https.Get("/metrics")->status, 401);
  EXPECT_EQ(https.Get("/api/state", {{"Authorization", "Bearer wrong"}})->status, 401);
  EXPECT_EQ(https.Get("/api/state", bearer("viewer"))->status, 200);
  EXPECT_EQ(https.Get("/metrics", bearer("viewer"))->status, 200);
  const httplib::Result viewer_button =
      https.Post("/api/jobs/job-000001/pause", bearer("viewer"), "", "text/plain");
  EXPECT_EQ(viewer_button->status, 403);
  EXPECT_THAT(viewer_button->body, HasSubstr("needs operator"));
  // An operator gets through to the job service (which knows no such job).
  EXPECT_EQ(https.Post("/api/jobs/job-000001/pause", bearer("operator"), "", "text/plain")->status,
            404);
  // Plain HTTP on the HTTPS port gets no answer.
  httplib::Client plain("127.0.0.1", *port);
  plain.set_read_timeout(2, 0);
  const httplib::Result refused = plain.Get("/api/state", bearer("admin"));
  EXPECT_TRUE(!refused || refused->status >= 400);
  gateway.Stop();
}

TEST_F(SecurityTest, BadSecurityFilesStopTheServerBeforeItOpensTheDatabase) {
  const auto start_with = [&](server::ServerSecurityFiles files) {
    server::FleetServerParams params;
    params.listen_address = "127.0.0.1:0";
    params.db_path = testing::UniqueTempPath("never") + ".db";
    params.security = std::move(files);
    server::FleetServer server(params);
    const absl::Status status = server.Start().status();
    EXPECT_FALSE(std::filesystem::exists(params.db_path)) << status;
    return status;
  };
  const server::ServerSecurityFiles good{Pki("server.crt"), Pki("server.key"), Pki("robot-ca.crt"),
                                         Pki("tokens.yaml")};
  server::ServerSecurityFiles files = good;
  files.key_path = Pki("robot-lely1.key");  // another certificate's key
  const absl::Status mismatch = start_with(files);
  EXPECT_EQ(mismatch.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(mismatch.message(), HasSubstr("is not the key of the certificate"));
  files = good;
  files.client_ca_path = Pki("tokens.yaml");  // not a certificate
  EXPECT_THAT(start_with(files).message(), HasSubstr("holds no PEM certificate"));
  files = good;
  files.tokens_path = Pki("missing.yaml");
  EXPECT_EQ(start_with(files).code(), absl::StatusCode::kNotFound);
  files = good;
  files.tokens_path = testing::UniqueTempPath("viewers-only") + ".yaml";
  {
    std::ofstream viewers(files.tokens_path);
    viewers << "tokens:\n  - {name: vic, role: viewer, sha256: " << std::string(64, 'a') << "}\n";
  }
  const absl::Status no_admin = start_with(files);
  EXPECT_EQ(no_admin.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(no_admin.message(), HasSubstr(files.tokens_path));
  EXPECT_THAT(no_admin.message(), HasSubstr("no token of role admin"));
  std::filesystem::remove(files.tokens_path);
  files = good;
  files.cert_path.clear();
  EXPECT_THAT(start_with(files).message(), HasSubstr("tls cert: no file given"));
}

}  // namespace
}  // namespace fleetnav
