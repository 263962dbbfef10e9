#include "load_operators.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <thread>

#include "absl/synchronization/mutex.h"
#include "load_report.hpp"
#include "load_tls.hpp"

namespace fleetnav::loadgen {
namespace {

std::shared_ptr<grpc::Channel> NewChannel(const LoadTarget& target, int index) {
  return NewOperatorChannel(target, index);
}

constexpr int kLargeMarkers = 100'000;
constexpr int kLargeRouteActions = 10'000;

bool WriteAll(int fd, const std::string& data) {
  for (size_t done = 0; done < data.size();) {
    const ssize_t n = write(fd, data.data() + done, data.size() - done);
    if (n <= 0) return false;
    done += static_cast<size_t>(n);
  }
  return true;
}

std::string ReadAll(int fd) {
  std::string out;
  char buffer[4096];
  for (ssize_t n; (n = read(fd, buffer, sizeof buffer)) > 0;) out.append(buffer, n);
  return out;
}

}  // namespace

bool PrepareRoute(v1::FleetService::Stub* fleet, const SiteOptions& site) {
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
  const int actions = site.large ? kLargeRouteActions : 1;
  for (int i = 0; i < actions; ++i) {
    v1::StraightAction* straight = route.mutable_route()->add_actions()->mutable_straight();
    straight->set_distance_m(1.0);
    straight->set_speed_mps(0.2);
  }
  v1::PutRouteResponse route_response;
  if (!fleet->PutRoute(&route_context, route, &route_response).ok()) return false;
  if (site.large) {
    grpc::ClientContext markers_context;
    v1::PutMarkerSetRequest markers;
    markers.mutable_marker_set()->set_map_id("loadgen");
    for (int i = 1; i <= kLargeMarkers; ++i) {
      v1::StripeMarker* marker = markers.mutable_marker_set()->add_markers();
      marker->set_id(i);
      marker->mutable_pose()->set_x_m(0.1 * (i % 100));
      marker->mutable_pose()->set_y_m(0.1 * ((i / 100) % 100));
      marker->set_length_m(0.5);
      marker->set_kind(v1::MARKER_KIND_CALIBRATION);
    }
    v1::PutMarkerSetResponse markers_response;
    if (!fleet->PutMarkerSet(&markers_context, markers, &markers_response).ok()) return false;
  }
  if (site.big_map_mb > 0) {
    const int side = static_cast<int>(std::sqrt(site.big_map_mb * 1e6));
    grpc::ClientContext big_context;
    big_context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(60));
    v1::PutMapRequest big;
    big.set_map_id("loadgen-big");
    big.mutable_grid()->set_width(side);
    big.mutable_grid()->set_height(side);
    big.mutable_grid()->set_resolution_m(0.05);
    big.mutable_grid()->set_cells(std::string(static_cast<size_t>(side) * side, '\0'));
    v1::PutMapResponse big_response;
    if (!fleet->PutMap(&big_context, big, &big_response).ok()) return false;
  }
  // A route no loadgen agent can drive (a turn), for jobs that stay queued under watch.
  grpc::ClientContext idle_context;
  v1::PutRouteRequest idle;
  idle.mutable_route()->set_name("loadgen-idle");
  idle.mutable_route()->set_map_id("loadgen");
  idle.mutable_route()->add_actions()->mutable_turn()->set_angle_rad(1.0);
  idle.mutable_route()->mutable_actions(0)->mutable_turn()->set_yaw_rate_radps(0.3);
  v1::PutRouteResponse idle_response;
  return fleet->PutRoute(&idle_context, idle, &idle_response).ok();
}

/// What the operators measured.
OperatorReport RunOperators(const LoadTarget& server, const OperatorOptions& options,
                            const std::atomic<bool>& stop) {
  const int submitters = options.submitters;
  const double rate_hz = options.rate_hz;
  std::mutex mutex;
  OperatorReport report;
  std::vector<std::thread> operators;
  std::ofstream acked;
  if (!options.acked_path.empty()) acked.open(options.acked_path, std::ios::app);
  for (int s = 0; s < submitters; ++s) {
    operators.emplace_back([&, s] {
      auto stub = v1::FleetService::NewStub(NewChannel(server, 1000 + s));
      const auto period = std::chrono::duration<double>(1.0 / rate_hz);
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
        bool ok = stub->SubmitJob(&context, request, &response).ok();
        while (!ok && !stop.load() && (SteadyNowNs() - start) * 1e-9 < options.retry_s) {
          std::this_thread::sleep_for(std::chrono::milliseconds(100));
          grpc::ClientContext again;
          again.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(5));
          ok = stub->SubmitJob(&again, request, &response).ok();
        }
        const double ms = (SteadyNowNs() - start) * 1e-6;
        if (ok && acked.is_open()) {
          std::lock_guard<std::mutex> lock(mutex);
          acked << request.idempotency_key() << ' ' << response.job().job_id() << '\n';
        }
        if (ok && i % options.watch_every == 0) {
          // Watched until its first event, or until it is assigned to a robot.
          grpc::ClientContext watch_context;
          watch_context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(5));
          v1::WatchJobRequest watch;
          watch.set_job_id(response.job().job_id());
          auto reader = stub->WatchJob(&watch_context, watch);
          v1::JobEvent event;
          bool got = reader->Read(&event);
          while (got && options.until_assigned && event.type() != v1::JOB_EVENT_TYPE_ASSIGNED) {
            got = reader->Read(&event);
          }
          const double dispatch_ms = (SteadyNowNs() - start) * 1e-6;
          watch_context.TryCancel();
          (void)reader->Finish();
          std::lock_guard<std::mutex> lock(mutex);
          report.watches += got;
          if (got && options.until_assigned) report.dispatch_ms.push_back(dispatch_ms);
        }
        {
          std::lock_guard<std::mutex> lock(mutex);
          if (ok) {
            report.submit_ms.push_back(ms);
          } else {
            ++report.submit_errors;
          }
        }
        next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(period);
        std::this_thread::sleep_until(next);
      }
    });
  }
  if (options.site.big_map_mb > 0) {
    // One more operator submits go-to-goal jobs on the big map, 5 a second.
    operators.emplace_back([&] {
      auto stub = v1::FleetService::NewStub(NewChannel(server, 2000));
      auto next = std::chrono::steady_clock::now();
      while (!stop.load()) {
        grpc::ClientContext context;
        context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(5));
        v1::SubmitJobRequest request;
        request.mutable_goal()->set_map_id("loadgen-big");
        request.mutable_goal()->mutable_goal()->set_x_m(1.0);
        request.mutable_goal()->mutable_goal()->set_y_m(1.0);
        v1::SubmitJobResponse response;
        const int64_t start = SteadyNowNs();
        const bool ok = stub->SubmitJob(&context, request, &response).ok();
        const double ms = (SteadyNowNs() - start) * 1e-6;
        {
          std::lock_guard<std::mutex> lock(mutex);
          if (ok) {
            report.big_submit_ms.push_back(ms);
          } else {
            ++report.submit_errors;
          }
        }
        next += std::chrono::milliseconds(200);
        std::this_thread::sleep_until(next);
      }
    });
  }
  for (std::thread& t : operators) t.join();
  return report;
}

void OperatorProcess::Go() { (void)WriteAll(to_child_, "G"); }

bool OperatorProcess::Start(const LoadTarget& server, const OperatorOptions& options) {
  int to_child[2], from_child[2];
  if (pipe(to_child) != 0 || pipe(from_child) != 0) return false;
  pid_ = fork();
  if (pid_ < 0) return false;
  if (pid_ == 0) {
    close(to_child[1]);
    close(from_child[0]);
    _exit(Child(server, options, to_child[0], from_child[1]));
  }
  close(to_child[0]);
  close(from_child[1]);
  to_child_ = to_child[1];
  from_child_ = from_child[0];
  char status = 'E';
  return read(from_child_, &status, 1) == 1 && status == 'R';
}

OperatorReport OperatorProcess::Stop() {
  close(to_child_);
  const std::string text = ReadAll(from_child_);
  close(from_child_);
  int status = 0;
  waitpid(pid_, &status, 0);
  OperatorReport report;
  nlohmann::json json = nlohmann::json::parse(text, nullptr, false);
  if (json.is_discarded() || !json.is_object()) return report;
  report.submit_ms = json.value("submit_ms", std::vector<double>{});
  report.dispatch_ms = json.value("dispatch_ms", std::vector<double>{});
  report.big_submit_ms = json.value("big_submit_ms", std::vector<double>{});
  report.submit_errors = json.value("submit_errors", uint64_t{0});
  report.watches = json.value("watches", uint64_t{0});
  return report;
}

int OperatorProcess::Child(const LoadTarget& server, const OperatorOptions& options, int in,
                           int out) {
  auto control = v1::FleetService::NewStub(NewChannel(server, -1));
  if (!PrepareRoute(control.get(), options.site)) {
    (void)WriteAll(out, "E");
    return 1;
  }
  (void)WriteAll(out, "R");
  char go = 0;
  if (read(in, &go, 1) != 1) return 0;
  std::atomic<bool> stop{false};
  std::thread stopper([&] {
    (void)ReadAll(in);  // end of file: the parent closed its end
    stop.store(true);
  });
  OperatorReport report = RunOperators(server, options, stop);
  stopper.join();
  const nlohmann::json json = {{"submit_ms", report.submit_ms},
                               {"dispatch_ms", report.dispatch_ms},
                               {"big_submit_ms", report.big_submit_ms},
                               {"submit_errors", report.submit_errors},
                               {"watches", report.watches}};
  return WriteAll(out, json.dump()) ? 0 : 1;
}

void IdleWatchers::Open(const LoadTarget& server, int count) {
  auto control = v1::FleetService::NewStub(NewChannel(server, -2));
  grpc::ClientContext submit_context;
  v1::SubmitJobRequest submit;
  submit.set_route_name("loadgen-idle");
  v1::SubmitJobResponse job;
  if (!control->SubmitJob(&submit_context, submit, &job).ok()) return;
  for (int i = 0; i < 2 * count; ++i) {
    if (i % 100 == 0) stubs_.push_back(v1::FleetService::NewStub(NewChannel(server, 3000 + i)));
    auto stream = std::make_unique<Stream>();
    if (i % 2 == 0) {
      v1::WatchJobRequest request;
      request.set_job_id(job.job().job_id());
      stream->job = stubs_.back()->WatchJob(&stream->context, request);
      v1::JobEvent first;
      open_ += stream->job->Read(&first);
    } else {
      stream->fleet = stubs_.back()->WatchFleet(&stream->context, v1::WatchFleetRequest());
      v1::FleetUpdate first;
      open_ += stream->fleet->Read(&first);
    }
    streams_.push_back(std::move(stream));
  }
}

IdleWatchers::~IdleWatchers() {
  for (auto& stream : streams_) stream->context.TryCancel();
  for (auto& stream : streams_) {
    if (stream->job) (void)stream->job->Finish();
    if (stream->fleet) (void)stream->fleet->Finish();
  }
}

}  // namespace fleetnav::loadgen
