// fleetnavd: the fleet server. Wiring only: flags -> FleetServer -> serve until SIGINT/SIGTERM.
#include <csignal>
#include <pthread.h>

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include "fleetnav/server/rpc/fleet_server.hpp"

int main(int argc, char** argv) {
  // SIGINT/SIGTERM are blocked in every thread and taken synchronously below.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

  fleetnav::server::FleetServerParams params;
  CLI::App app{"fleetnavd: fleet navigation server (FleetService + AgentService)"};
  app.add_option("--listen", params.listen_address, "address to serve on (host:port; port 0 = any)")
      ->capture_default_str();
  app.add_option("--db", params.db_path, "SQLite database file (created if missing)")
      ->capture_default_str();
  app.add_option("--stale-after-s", params.registry.stale_after_s,
                 "seconds without telemetry before a robot shows as stale")
      ->capture_default_str();
  app.add_option("--max-message-bytes", params.max_message_bytes, "largest request accepted")
      ->capture_default_str();
  std::string port_file;
  app.add_option("--port-file", port_file, "write the bound port to this file once serving");
  CLI11_PARSE(app, argc, argv);

  fleetnav::server::FleetServer server(params);
  absl::StatusOr<int> port = server.Start();
  if (!port.ok()) {
    spdlog::error("fleetnavd: {}", port.status().ToString());
    return 1;
  }
  spdlog::info("fleetnavd serving on port {} (db {})", *port, params.db_path);
  if (!port_file.empty()) {
    FILE* f = std::fopen(port_file.c_str(), "w");
    if (f != nullptr) {
      std::fprintf(f, "%d\n", *port);
      std::fclose(f);
    }
  }

  int signal_number = 0;
  sigwait(&stop_signals, &signal_number);
  spdlog::info("fleetnavd: signal {}, shutting down", signal_number);
  server.Shutdown();
  server.Wait();
  return 0;
}
