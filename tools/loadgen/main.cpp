// fleetnav-loadgen: N agents streaming telemetry at R Hz plus M operators submitting and
// watching jobs against a running fleetnavd on loopback; prints one JSON object.
#include <grpcpp/create_channel.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <cmath>
#include <iostream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <thread>

#include "fleetnav/v1/fleet_service.grpc.pb.h"
#include "load_agents.hpp"
#include "load_report.hpp"

namespace {

using fleetnav::loadgen::LoadAgent;
using fleetnav::loadgen::SteadyNowNs;
namespace v1 = fleetnav::v1;

std::shared_ptr<grpc::Channel> NewChannel(const std::string& server, int index) {
  grpc::ChannelArguments args;
  args.SetInt(GRPC_ARG_ENABLE_RETRIES, 0);             // no retry buffering on long streams
  args.SetInt(GRPC_ARG_USE_LOCAL_SUBCHANNEL_POOL, 1);  // one connection per channel
  args.SetInt("fleetnav.loadgen.channel", index);
  return grpc::CreateCustomChannel(server, grpc::InsecureChannelCredentials(), args);
}

/// A map and a route for the submitters' jobs.
bool PrepareRoute(v1::FleetService::Stub* fleet) {
  grpc::ClientContext map_context;
  v1::PutMapRequest map;
  map.set_map_id("loadgen");
  v1::OccupancyGrid* grid = map.mutable_grid();
  grid->set_width(100);
  grid->set_height(100);
  grid->set_resolution_m(0.1);
  grid->set_cells(std::string(100 * 100, '\0'));
  v1::PutMapResponse map_response;
  if (!fleet->PutMap(&map_context, map, &map_response).ok()) return false;
  grpc::ClientContext route_context;
  v1::PutRouteRequest route;
  route.mutable_route()->set_name("loadgen-route");
  route.mutable_route()->set_map_id("loadgen");
  route.mutable_route()->add_actions()->mutable_straight()->set_distance_m(1.0);
  route.mutable_route()->mutable_actions(0)->mutable_straight()->set_speed_mps(0.2);
  v1::PutRouteResponse route_response;
  return fleet->PutRoute(&route_context, route, &route_response).ok();
}

}  // namespace

int main(int argc, char** argv) {
  std::string server = "127.0.0.1:50051";
  int agents = 100, submitters = 2;
  double rate_hz = 10.0, duration_s = 10.0, submit_rate_hz = 20.0;
  pid_t server_pid = 0;
  bool json = false;
  CLI::App app{"fleetnav-loadgen: load fleetnavd with agents and operators"};
  app.add_option("--server", server, "fleetnavd address")->capture_default_str();
  app.add_option("--agents", agents, "agent streams")->capture_default_str();
  app.add_option("--rate-hz", rate_hz, "telemetry per agent per second")->capture_default_str();
  app.add_option("--duration-s", duration_s, "measured time")->capture_default_str();
  app.add_option("--submitters", submitters, "operators submitting jobs")->capture_default_str();
  app.add_option("--submit-rate-hz", submit_rate_hz, "jobs per submitter per second")
      ->capture_default_str();
  app.add_option("--server-pid", server_pid, "fleetnavd's pid, for its CPU and memory");
  app.add_flag("--json", json, "print one JSON object (the only output mode)");
  CLI11_PARSE(app, argc, argv);
  if (agents < 0 || submitters < 0 || !(rate_hz > 0) || !(duration_s > 0)) {
    std::cerr << "fleetnav-loadgen: --agents/--submitters must be >= 0, rates and duration > 0\n";
    return 2;
  }

  auto control = v1::FleetService::NewStub(NewChannel(server, -1));
  if (submitters > 0 && !PrepareRoute(control.get())) {
    std::cerr << "fleetnav-loadgen: cannot reach fleetnavd at " << server << '\n';
    return 1;
  }

  // Agents: about 200 streams per connection.
  const int channel_count = std::max(1, (agents + 199) / 200);
  std::vector<std::unique_ptr<v1::AgentService::Stub>> stubs;
  for (int c = 0; c < channel_count; ++c) {
    stubs.push_back(v1::AgentService::NewStub(NewChannel(server, c)));
  }
  std::vector<std::unique_ptr<LoadAgent>> fleet;
  for (int i = 0; i < agents; ++i) {
    fleet.push_back(
        std::make_unique<LoadAgent>(stubs[i % channel_count].get(), "load-" + std::to_string(i)));
  }
  const auto connect_deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  int ready = 0;
  while (std::chrono::steady_clock::now() < connect_deadline) {
    ready = 0;
    for (const auto& a : fleet) ready += a->ready();
    if (ready == agents) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }

  std::atomic<bool> stop{false};
  std::mutex submit_mutex;
  std::vector<double> submit_ms;
  uint64_t submit_errors = 0, watches = 0;
  std::vector<std::thread> operators;
  for (int s = 0; s < submitters; ++s) {
    operators.emplace_back([&, s] {
      auto stub = v1::FleetService::NewStub(NewChannel(server, 1000 + s));
      const auto period = std::chrono::duration<double>(1.0 / submit_rate_hz);
      auto next = std::chrono::steady_clock::now();
      for (int i = 0; !stop.load(); ++i) {
        grpc::ClientContext context;
        context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(5));
        v1::SubmitJobRequest request;
        request.set_route_name("loadgen-route");
        request.set_robot_id("");
        request.set_idempotency_key("lg-" + std::to_string(SteadyNowNs()) + "-" +
                                    std::to_string(s) + "-" + std::to_string(i));
        v1::SubmitJobResponse response;
        const int64_t start = SteadyNowNs();
        const bool ok = stub->SubmitJob(&context, request, &response).ok();
        const double ms = (SteadyNowNs() - start) * 1e-6;
        if (ok && i % 10 == 0) {  // every tenth job is watched until its first event
          grpc::ClientContext watch_context;
          watch_context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(2));
          v1::WatchJobRequest watch;
          watch.set_job_id(response.job().job_id());
          auto reader = stub->WatchJob(&watch_context, watch);
          v1::JobEvent event;
          const bool got = reader->Read(&event);
          watch_context.TryCancel();
          (void)reader->Finish();
          std::lock_guard<std::mutex> lock(submit_mutex);
          watches += got;
        }
        {
          std::lock_guard<std::mutex> lock(submit_mutex);
          if (ok) {
            submit_ms.push_back(ms);
          } else {
            ++submit_errors;
          }
        }
        next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(period);
        std::this_thread::sleep_until(next);
      }
    });
  }

  // Pacing: every agent gets one message per period, spread evenly across the period.
  const double cpu_start = server_pid > 0 ? fleetnav::loadgen::ProcessCpuSeconds(server_pid) : -1;
  const int64_t start_ns = SteadyNowNs();
  const int64_t end_ns = start_ns + static_cast<int64_t>(duration_s * 1e9);
  const int64_t period_ns = static_cast<int64_t>(1e9 / rate_hz);
  uint64_t skipped = 0, scheduled = 0;
  std::vector<double> latencies;
  for (int64_t tick_ns = start_ns; tick_ns < end_ns; tick_ns += period_ns) {
    const uint64_t sequence = static_cast<uint64_t>((tick_ns - start_ns) / period_ns);
    for (int i = 0; i < agents; ++i) {
      const int64_t due = tick_ns + period_ns * i / std::max(agents, 1);
      const int64_t now = SteadyNowNs();
      if (due > now) std::this_thread::sleep_for(std::chrono::nanoseconds(due - now));
      ++scheduled;
      if (!fleet[i]->Send(due, sequence)) ++skipped;
    }
    for (auto& a : fleet) {
      std::vector<double> l = a->TakeLatencies();
      latencies.insert(latencies.end(), l.begin(), l.end());
    }
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(200));  // let the last writes finish
  const double elapsed_s = (SteadyNowNs() - start_ns) * 1e-9;
  const double cpu_end = server_pid > 0 ? fleetnav::loadgen::ProcessCpuSeconds(server_pid) : -1;
  const double rss_mb = server_pid > 0 ? fleetnav::loadgen::ProcessRssMb(server_pid) : -1;
  stop.store(true);
  for (std::thread& t : operators) t.join();
  uint64_t delivered = 0;
  for (auto& a : fleet) {
    std::vector<double> l = a->TakeLatencies();
    latencies.insert(latencies.end(), l.begin(), l.end());
    delivered += a->completed();
    a->Cancel();
  }
  for (auto& a : fleet) {
    while (!a->done()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }

  nlohmann::json out = {
      {"agents", agents},
      {"agents_connected", ready},
      {"rate_hz", rate_hz},
      {"duration_s", elapsed_s},
      {"telemetry_msgs_per_s", delivered / elapsed_s},
      {"telemetry_target_msgs_per_s", agents * rate_hz},
      {"telemetry_skipped_fraction", scheduled ? static_cast<double>(skipped) / scheduled : 0.0},
      {"telemetry_lag_ms_p50", fleetnav::loadgen::Percentile(latencies, 50)},
      {"telemetry_lag_ms_p99", fleetnav::loadgen::Percentile(latencies, 99)},
      {"submitters", submitters},
      {"jobs_submitted", submit_ms.size()},
      {"submit_errors", submit_errors},
      {"watches", watches},
      {"submit_ms_p50", fleetnav::loadgen::Percentile(submit_ms, 50)},
      {"submit_ms_p99", fleetnav::loadgen::Percentile(submit_ms, 99)},
      {"server_cpu_percent", cpu_start >= 0 ? 100.0 * (cpu_end - cpu_start) / elapsed_s : -1.0},
      {"server_rss_mb", rss_mb}};
  std::cout << out.dump() << std::endl;
  return 0;
}
