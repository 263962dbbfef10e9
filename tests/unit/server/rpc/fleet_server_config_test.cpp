#include "fleetnav/server/rpc/fleet_server_config.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace fleetnav::server {
namespace {

using ::testing::HasSubstr;

TEST(FleetServerConfigTest, EmptyConfigKeepsTheDefaults) {
  absl::StatusOr<FleetServerConfig> config = ParseFleetServerConfig("");
  ASSERT_TRUE(config.ok()) << config.status();
  EXPECT_EQ(config->params.listen_address, "127.0.0.1:50051");
  EXPECT_DOUBLE_EQ(config->params.jobs.lost_robot_timeout_s, 30.0);
  EXPECT_EQ(config->log_level, "info");
}

TEST(FleetServerConfigTest, EveryKeyIsRead) {
  absl::StatusOr<FleetServerConfig> config = ParseFleetServerConfig(R"(
listen: 0.0.0.0:6000
db: /tmp/x.db
log_level: debug
agent_threads: 4
limits: {max_message_bytes: 2048, max_page_size: 50}
timeouts: {stale_after_s: 1.5, lost_robot_timeout_s: 9, dispatch_period_s: 0.1}
)");
  ASSERT_TRUE(config.ok()) << config.status();
  EXPECT_EQ(config->params.listen_address, "0.0.0.0:6000");
  EXPECT_EQ(config->params.db_path, "/tmp/x.db");
  EXPECT_EQ(config->log_level, "debug");
  EXPECT_EQ(config->params.agent_stream_threads, 4);
  EXPECT_EQ(config->params.max_message_bytes, 2048);
  EXPECT_EQ(config->params.jobs.max_page_size, 50);
  EXPECT_DOUBLE_EQ(config->params.registry.stale_after_s, 1.5);
  EXPECT_DOUBLE_EQ(config->params.jobs.lost_robot_timeout_s, 9.0);
  EXPECT_DOUBLE_EQ(config->params.dispatch_period_s, 0.1);
}

TEST(FleetServerConfigTest, TlsFilesAndInsecureAreRead) {
  absl::StatusOr<FleetServerConfig> config = ParseFleetServerConfig(R"(
tls: {cert: /etc/fleetnav/server.crt, key: /etc/fleetnav/server.key,
      client_ca: /etc/fleetnav/robot-ca.crt, tokens: /etc/fleetnav/tokens.yaml}
)");
  ASSERT_TRUE(config.ok()) << config.status();
  EXPECT_EQ(config->params.security.cert_path, "/etc/fleetnav/server.crt");
  EXPECT_EQ(config->params.security.key_path, "/etc/fleetnav/server.key");
  EXPECT_EQ(config->params.security.client_ca_path, "/etc/fleetnav/robot-ca.crt");
  EXPECT_EQ(config->params.security.tokens_path, "/etc/fleetnav/tokens.yaml");
  EXPECT_FALSE(config->insecure);
  EXPECT_TRUE(ParseFleetServerConfig("insecure: true")->insecure);
  EXPECT_THAT(ParseFleetServerConfig("tls: {certificate: a}").status().message(),
              HasSubstr("tls: unknown key 'certificate'"));
}

TEST(FleetServerConfigTest, AKeyOfAnotherShapeIsRefusedNotThrown) {
  // A mapping as a key (yaml-cpp threw from the key check before).
  EXPECT_EQ(ParseFleetServerConfig("limits:\n  {max_page_size: 1}: 3\n").status().code(),
            absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(ParseFleetServerConfig("[1, 2]: x\n").status().code(),
            absl::StatusCode::kInvalidArgument);
}

TEST(FleetServerConfigTest, TheShippedConfigServesTls) {
  const absl::StatusOr<FleetServerConfig> config =
      LoadFleetServerConfig(std::string(FLEETNAV_DEPLOY_DIR) + "/fleetnavd.yaml");
  ASSERT_TRUE(config.ok()) << config.status();
  EXPECT_FALSE(config->insecure);
  EXPECT_FALSE(config->params.security.cert_path.empty());
  EXPECT_FALSE(config->params.security.key_path.empty());
  EXPECT_FALSE(config->params.security.client_ca_path.empty());
  EXPECT_FALSE(config->params.security.tokens_path.empty());
}

TEST(FleetServerConfigTest, BadConfigsNameTheKey) {
  for (const auto& [yaml, text] : std::vector<std::pair<std::string, std::string>>{
           {"lissten: x", "lissten"},
           {"timeouts: {stale_after_s: -1}", "stale_after_s"},
           {"timeouts: {stale_after_s: abc}", "stale_after_s"},
           {"limits: {max_message_bytes: 10}", "max_message_bytes"},
           {"log_level: loud", "log_level"},
           {"agent_threads: 0", "agent_threads"},
           {"timeouts: {nap_s: 3}", "nap_s"},
           {"listen: [1, 2", "config"}}) {
    SCOPED_TRACE(yaml);
    absl::StatusOr<FleetServerConfig> config = ParseFleetServerConfig(yaml);
    ASSERT_FALSE(config.ok());
    EXPECT_EQ(config.status().code(), absl::StatusCode::kInvalidArgument);
    EXPECT_THAT(config.status().message(), HasSubstr(text));
  }
}

TEST(FleetServerConfigTest, AgentStreamThreadsMustBeBetweenOneAndSixtyFour) {
  FleetServerParams params;
  EXPECT_TRUE(params.Validate().ok());
  for (int threads : {0, -1, 65}) {
    params.agent_stream_threads = threads;
    const absl::Status status = params.Validate();
    EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument) << threads;
    EXPECT_THAT(status.message(), HasSubstr("agent_stream_threads"));
  }
  params.agent_stream_threads = 64;
  EXPECT_TRUE(params.Validate().ok());
}

TEST(FleetServerConfigTest, ChargingRoutesAndThresholdsAreReadAndChecked) {
  absl::StatusOr<FleetServerConfig> config = ParseFleetServerConfig(
      "charging: {below_fraction: 0.25, charged_fraction: 0.8, routes: {barn: barn-charge}}\n");
  ASSERT_TRUE(config.ok()) << config.status();
  EXPECT_DOUBLE_EQ(config->params.jobs.charge_below_fraction, 0.25);
  EXPECT_DOUBLE_EQ(config->params.jobs.charged_fraction, 0.8);
  EXPECT_EQ(config->params.jobs.charging_routes.at("barn"), "barn-charge");

  absl::StatusOr<FleetServerConfig> inverted =
      ParseFleetServerConfig("charging: {below_fraction: 0.9, charged_fraction: 0.5}\n");
  EXPECT_EQ(inverted.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(inverted.status().message(), HasSubstr("below_fraction < charged_fraction"));
  EXPECT_THAT(ParseFleetServerConfig("charging: {routes: [barn]}\n").status().message(),
              HasSubstr("charging.routes: expected {map_id: route_name"));
  EXPECT_THAT(ParseFleetServerConfig("charging: {below: 0.1}\n").status().message(),
              HasSubstr("charging: unknown key 'below'"));
}

TEST(FleetServerConfigTest, MissingFileIsNotFound) {
  EXPECT_EQ(LoadFleetServerConfig("/nonexistent/fleetnavd.yaml").status().code(),
            absl::StatusCode::kNotFound);
}

}  // namespace
}  // namespace fleetnav::server
