#include "fleetnav/server/http/http_gateway.hpp"

#include <httplib.h>

#include <chrono>
#include <nlohmann/json.hpp>

#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/server/http/dashboard_assets.hpp"
#include "fleetnav/server/http/dashboard_json.hpp"
#include "http_listener.hpp"

namespace fleetnav::server::http {
namespace {

int HttpCode(const absl::Status& status) {
  switch (status.code()) {
    case absl::StatusCode::kOk:
      return 200;
    case absl::StatusCode::kNotFound:
      return 404;
    case absl::StatusCode::kInvalidArgument:
      return 400;
    case absl::StatusCode::kFailedPrecondition:
    case absl::StatusCode::kAlreadyExists:
      return 409;
    case absl::StatusCode::kUnauthenticated:
      return 401;
    case absl::StatusCode::kPermissionDenied:
      return 403;
    default:
      return 500;
  }
}

void SendError(httplib::Response& res, const absl::Status& status) {
  res.status = HttpCode(status);
  res.set_content(nlohmann::json{{"error", std::string(status.message())}}.dump(),
                  "application/json");
}

void SendJson(httplib::Response& res, const nlohmann::json& body) {
  res.set_header("Cache-Control", "no-store");
  res.set_content(body.dump(), "application/json");
}

}  // namespace

absl::Status HttpGatewayParams::Validate() const {
  RETURN_IF_ERROR(ValidateHttpListen(listen_address, cert_path, key_path, threads));
  if (!(push_rate_hz > 0.0 && push_rate_hz <= 50.0)) {
    return absl::InvalidArgumentError(
        absl::StrCat("http push rate: must be in (0, 50] Hz, got ", push_rate_hz));
  }
  return absl::OkStatus();
}

HttpGateway::HttpGateway(FleetApp* app, std::function<std::string()> render_metrics,
                         HttpGatewayParams params)
    : app_(app), render_metrics_(std::move(render_metrics)), params_(std::move(params)) {}

HttpGateway::~HttpGateway() { Stop(); }

absl::StatusOr<int> HttpGateway::Start() {
  if (absl::Status valid = params_.Validate(); !valid.ok()) return valid;
  ASSIGN_OR_RETURN(http_, MakeHttpServer(params_.cert_path, params_.key_path,
                                         params_.max_request_bytes, params_.threads));
  AddHandlers();
  ASSIGN_OR_RETURN(const int bound, BindHttpServer(http_.get(), params_.listen_address));
  listener_ = std::thread([this] { http_->listen_after_bind(); });
  return bound;
}

void HttpGateway::Stop() {
  if (http_ == nullptr || stopping_.exchange(true)) return;
  http_->stop();
  if (listener_.joinable()) listener_.join();
}

std::vector<Job> HttpGateway::UnfinishedJobs() {
  absl::MutexLock lock(&jobs_mutex_);
  const uint64_t changes = app_->job_changes();
  if (changes != jobs_read_at_) {
    storage::JobFilter unfinished;
    unfinished.states = {JobState::kQueued, JobState::kAssigned, JobState::kRunning,
                         JobState::kPaused};
    unfinished.page_size = 500;
    if (absl::StatusOr<storage::JobPage> page = app_->jobs().List(unfinished); page.ok()) {
      unfinished_jobs_ = std::move(page->jobs);
      jobs_read_at_ = changes;
    }
  }
  return unfinished_jobs_;
}

std::vector<RobotStop> HttpGateway::StopsInForce() {
  absl::MutexLock lock(&jobs_mutex_);
  const uint64_t changes = app_->stop_changes();
  if (changes != stops_read_at_) {
    if (absl::StatusOr<std::vector<RobotStop>> stops = app_->stops().InForce(); stops.ok()) {
      stops_ = *std::move(stops);
      stops_read_at_ = changes;
    }
  }
  return stops_;
}

std::string HttpGateway::StateJson() {
  return FleetStateJson(app_->registry().Snapshot(), UnfinishedJobs(), StopsInForce(),
                        app_->clock().UnixMs())
      .dump();
}

void HttpGateway::AddHandlers() {
  // Every request but the health check and the page's own assets shows a token on a TLS
  // server: a viewer's to read, an operator's for the buttons.
  const auto allowed = [this](const httplib::Request& req, httplib::Response& res, bool action) {
    AccessControl* access = app_->access().get();
    if (access == nullptr) return true;
    const absl::StatusOr<Caller> caller =
        access->AuthorizeHttp(action, req.get_header_value("Authorization"));
    if (caller.ok()) return true;
    SendError(res, caller.status());
    return false;
  };

  http_->Get("/healthz", [](const httplib::Request&, httplib::Response& res) {
    res.set_content("ok\n", "text/plain");
  });
  http_->Get("/metrics", [this, allowed](const httplib::Request& req, httplib::Response& res) {
    if (!allowed(req, res, false)) return;
    res.set_content(render_metrics_(), "text/plain; version=0.0.4");
  });
  for (const DashboardAsset& asset : DashboardAssets()) {
    const std::string path = asset.path == "/index.html" ? "/" : asset.path;
    for (const std::string& served : {path, asset.path}) {
      http_->Get(served, [asset](const httplib::Request&, httplib::Response& res) {
        res.set_content(std::string(asset.content), std::string(asset.content_type));
      });
    }
  }
  http_->Get("/api/state", [this, allowed](const httplib::Request& req, httplib::Response& res) {
    if (!allowed(req, res, false)) return;
    res.set_header("Cache-Control", "no-store");
    res.set_content(StateJson(), "application/json");
  });
  http_->Get("/api/events", [this, allowed](const httplib::Request& req, httplib::Response& res) {
    if (!allowed(req, res, false)) return;
    res.set_header("Cache-Control", "no-store");
    const auto period = std::chrono::duration<double>(1.0 / params_.push_rate_hz);
    res.set_chunked_content_provider(
        "text/event-stream", [this, period](size_t, httplib::DataSink& sink) {
          if (stopping_.load()) return false;
          const std::string event = absl::StrCat("event: state\ndata: ", StateJson(), "\n\n");
          if (!sink.write(event.data(), event.size())) return false;
          std::this_thread::sleep_for(period);
          return !stopping_.load();
        });
  });
  http_->Get("/api/maps", [this, allowed](const httplib::Request& req, httplib::Response& res) {
    if (!allowed(req, res, false)) return;
    absl::StatusOr<std::vector<MapInfo>> maps = app_->maps().List();
    if (!maps.ok()) return SendError(res, maps.status());
    nlohmann::json list = nlohmann::json::array();
    for (const MapInfo& info : *maps)
      list.push_back({{"map_id", info.map_id}, {"version", info.version}});
    SendJson(res, list);
  });
  http_->Get(R"(/api/maps/([a-z0-9_-]{1,64}))", [this, allowed](const httplib::Request& req,
                                                                httplib::Response& res) {
    if (!allowed(req, res, false)) return;
    const std::string map_id = req.matches[1];
    absl::StatusOr<std::shared_ptr<const storage::StoredMap>> map = app_->maps().Get(map_id, 0);
    if (!map.ok()) return SendError(res, map.status());
    nlohmann::json body = MapJson(map_id, (*map)->info.version, (*map)->grid);
    absl::StatusOr<std::shared_ptr<const storage::StoredMarkerSet>> markers =
        app_->site().GetMarkerSet(map_id, 0);
    absl::StatusOr<std::vector<storage::StoredRoute>> stored = app_->site().ListRoutes(map_id);
    std::vector<Route> routes;
    if (stored.ok()) {
      for (const storage::StoredRoute& route : *stored) routes.push_back(route.route);
    }
    body["site"] = SiteJson(markers.ok() ? &(*markers)->markers : nullptr, routes);
    const std::shared_ptr<const storage::StoredZoneSet> zones = app_->zones().Latest(map_id);
    body["zones"] = ZonesJson(zones != nullptr ? zones->version : 0,
                              zones != nullptr ? &zones->zones : nullptr);
    SendJson(res, body);
  });
  // Operators' stops: {"zone": Z, "map_id": M (optional), "reason": R} or {} for the whole
  // fleet; POST /api/stops makes it, POST /api/stops/resume clears it.
  http_->Post(R"(/api/stops(/resume)?)", [this, allowed](const httplib::Request& req,
                                                         httplib::Response& res) {
    if (!allowed(req, res, true)) return;
    const nlohmann::json body = nlohmann::json::parse(req.body.empty() ? "{}" : req.body, nullptr,
                                                      /*allow_exceptions=*/false);
    if (!body.is_object()) {
      return SendError(res, absl::InvalidArgumentError("body: expected a JSON object"));
    }
    const auto text = [&](const char* key) {
      return body.contains(key) && body[key].is_string() ? body[key].get<std::string>() : "";
    };
    const bool resume = req.matches[1].length() > 0;
    absl::StatusOr<RobotStop> done =
        resume ? app_->stops().Resume(text("map_id"), text("zone"))
               : app_->stops().Stop(text("map_id"), text("zone"),
                                    text("reason").empty() ? "from the dashboard" : text("reason"));
    if (!done.ok()) return SendError(res, done.status());
    SendJson(res, StopsJson({*done}).at(0));
  });
  http_->Get(R"(/api/jobs/([A-Za-z0-9_-]{1,64})/events)",
             [this, allowed](const httplib::Request& req, httplib::Response& res) {
               if (!allowed(req, res, false)) return;
               absl::StatusOr<std::vector<JobEvent>> events =
                   app_->jobs().Events(req.matches[1], 0);
               if (!events.ok()) return SendError(res, events.status());
               SendJson(res, JobEventsJson(*events));
             });
  http_->Post(
      R"(/api/jobs/([A-Za-z0-9_-]{1,64})/(pause|resume|cancel))",
      [this, allowed](const httplib::Request& req, httplib::Response& res) {
        if (!allowed(req, res, true)) return;
        const std::string job_id = req.matches[1];
        const std::string verb = req.matches[2];
        absl::StatusOr<Job> job =
            verb == "pause"    ? app_->jobs().Pause(job_id, "paused from the dashboard")
            : verb == "resume" ? app_->jobs().Resume(job_id)
                               : app_->jobs().Cancel(job_id, "cancelled from the dashboard");
        if (!job.ok()) return SendError(res, job.status());
        SendJson(res, {{"job_id", job->job_id}, {"state", std::string(JobStateName(job->state))}});
      });
  http_->set_error_handler([](const httplib::Request&, httplib::Response& res) {
    if (res.body.empty()) {
      res.set_content(nlohmann::json{{"error", res.status == 413   ? "request too large"
                                               : res.status == 404 ? "no such page"
                                                                   : "bad request"}}
                          .dump(),
                      "application/json");
    }
  });
}

}  // namespace fleetnav::server::http
