// fleetnav-vda5050: VDA 5050 2.0 vehicles on an MQTT broker as fleetnav robots (docs/vda5050.md).
// Wiring only: flags -> MosquittoClient + VdaBridge -> run until SIGINT/SIGTERM.
#include <grpcpp/create_channel.h>
#include <pthread.h>

#include <CLI/CLI.hpp>
#include <csignal>
#include <cstdio>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/clock.hpp"
#include "fleetnav/core/stop_signals.hpp"
#include "fleetnav/core/version.hpp"
#include "fleetnav/proto/server_target.hpp"
#include "fleetnav/vda5050/mqtt_client.hpp"
#include "fleetnav/vda5050/vda_bridge.hpp"

namespace {

void Print(const std::string& line) {
  std::fprintf(stderr, "%s\n", line.c_str());
  std::fflush(stderr);
}

}  // namespace

int main(int argc, char** argv) {
  sigset_t stop_signals = fleetnav::BlockStopSignals();

  CLI::App app{"fleetnav-vda5050: VDA 5050 2.0 vehicles on an MQTT broker as fleetnav robots"};
  app.set_version_flag("--version", std::string(fleetnav::Version()));
  std::string broker_host = "127.0.0.1", server = "127.0.0.1:50051";
  int broker_port = 1883;
  double broker_wait_s = 10.0, stats_period_s = 10.0;
  fleetnav::vda5050::BridgeParams params;
  app.add_option("--broker-host", broker_host, "MQTT broker host")->capture_default_str();
  app.add_option("--broker-port", broker_port, "MQTT broker port")
      ->check(CLI::Range(1, 65535))
      ->capture_default_str();
  app.add_option("--broker-wait-s", broker_wait_s,
                 "how long to wait for the broker at start (then exit 1)")
      ->capture_default_str();
  app.add_option("--server", server,
                 "fleetnavd address, or its replicas' IP:port list separated by commas")
      ->capture_default_str();
  app.add_option("--interface", params.interface_name,
                 "the topics' first level (VDA 5050 §6.3): INTERFACE/v2/MANUFACTURER/SERIAL/TOPIC")
      ->capture_default_str();
  app.add_option("--kind", params.kind,
                 "the fleetnav robot kind that stands for the vehicles (footprint, planning); "
                 "vehicles of other kinematics or larger are not registered")
      ->capture_default_str();
  app.add_option("--node-spacing-m", params.node_spacing_m,
                 "order nodes along a planned path at most this far apart")
      ->check(CLI::Range(0.2, 100.0))
      ->capture_default_str();
  app.add_option("--pass-deviation-m", params.order.pass_deviation_m,
                 "allowedDeviationXY of the nodes a vehicle passes")
      ->check(CLI::Range(0.0, 10.0))
      ->capture_default_str();
  app.add_option("--stats-period-s", stats_period_s,
                 "print the bridge's counters this often (0: never)")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  absl::StatusOr<std::string> target = fleetnav::ServerTarget(server);
  if (!target.ok()) {
    Print(absl::StrCat("fleetnav-vda5050: --server: ", target.status().message()));
    return 2;
  }
  fleetnav::SystemClock clock;
  fleetnav::vda5050::VdaBridge bridge(
      params, grpc::CreateChannel(*target, grpc::InsecureChannelCredentials()), &clock, Print);
  fleetnav::vda5050::MqttOptions options;
  options.host = broker_host;
  options.port = broker_port;
  options.client_id = absl::StrCat("fleetnav-vda5050-", getpid());
  absl::StatusOr<std::unique_ptr<fleetnav::vda5050::MosquittoClient>> mqtt =
      fleetnav::vda5050::MosquittoClient::Connect(
          options,
          [&bridge](const std::string& topic, const std::string& payload) {
            bridge.OnMessage(topic, payload);
          },
          // What was published meanwhile (QoS 1) goes out now; the vehicles say ONLINE again and
          // get their running orders again (VdaBridge).
          [](bool reconnected) {
            if (reconnected) Print("fleetnav-vda5050: broker back");
          },
          broker_wait_s);
  if (!mqtt.ok()) {
    Print(absl::StrCat("fleetnav-vda5050: ", mqtt.status().message()));
    return 1;
  }
  if (absl::Status started = bridge.Start(mqtt->get()); !started.ok()) {
    Print(absl::StrCat("fleetnav-vda5050: ", started.message()));
    return 2;
  }
  Print(absl::StrCat("fleetnav-vda5050: bridging ", params.interface_name, "/v2/+/+/* on ",
                     broker_host, ":", broker_port, " to fleetnavd at ", server, " as kind ",
                     params.kind));
  timespec period{};
  period.tv_sec = static_cast<time_t>(stats_period_s > 0 ? stats_period_s : 3600);
  while (true) {
    const int signal_number = sigtimedwait(&stop_signals, nullptr, &period);
    if (signal_number > 0) break;
    if (stats_period_s <= 0) continue;
    const fleetnav::vda5050::BridgeCounters c = bridge.counters();
    Print(absl::StrCat("fleetnav-vda5050: vehicles ", c.vehicles, ", states ", c.states,
                       ", orders ", c.orders, ", instant actions ", c.instant_actions,
                       "; left out: malformed ", c.refused_malformed, ", stale ", c.refused_stale,
                       ", unknown vehicle ", c.refused_unknown));
  }
  Print("fleetnav-vda5050: stopping");
  bridge.Stop();
  (*mqtt)->Disconnect();
  return 0;
}
