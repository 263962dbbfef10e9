#include "fleetnav/server/rpc/server_metrics.hpp"

#include <prometheus/metric_family.h>
#include <prometheus/text_serializer.h>

#include <chrono>

#include "absl/status/status.h"
#include "fleetnav/core/robot_state.hpp"

namespace fleetnav::server {
namespace {

/// Counts one call when its status is sent: method, code and the time since the call arrived.
class RpcMetricsInterceptor final : public grpc::experimental::Interceptor {
 public:
  RpcMetricsInterceptor(grpc::experimental::ServerRpcInfo* info, ServerMetrics* metrics)
      : method_(info->method() != nullptr ? info->method() : "unknown"),
        metrics_(metrics),
        started_(std::chrono::steady_clock::now()) {}

  void Intercept(grpc::experimental::InterceptorBatchMethods* methods) override {
    if (methods->QueryInterceptionHookPoint(
            grpc::experimental::InterceptionHookPoints::PRE_SEND_STATUS)) {
      metrics_->ObserveRpc(
          method_, methods->GetSendStatus().error_code(),
          std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count());
    }
    methods->Proceed();
  }

 private:
  std::string method_;
  ServerMetrics* metrics_;
  std::chrono::steady_clock::time_point started_;
};

class RpcMetricsFactory final : public grpc::experimental::ServerInterceptorFactoryInterface {
 public:
  explicit RpcMetricsFactory(ServerMetrics* metrics) : metrics_(metrics) {}
  grpc::experimental::Interceptor* CreateServerInterceptor(
      grpc::experimental::ServerRpcInfo* info) override {
    return new RpcMetricsInterceptor(info, metrics_);
  }

 private:
  ServerMetrics* metrics_;
};

prometheus::MetricFamily Family(const std::string& name, const std::string& help,
                                prometheus::MetricType type) {
  prometheus::MetricFamily family;
  family.name = name;
  family.help = help;
  family.type = type;
  return family;
}

void AddSample(prometheus::MetricFamily& family, const std::string& label, const std::string& value,
               double sample) {
  prometheus::ClientMetric metric;
  if (!label.empty()) metric.label.push_back({label, value});
  if (family.type == prometheus::MetricType::Counter) {
    metric.counter.value = sample;
  } else {
    metric.gauge.value = sample;
  }
  family.metric.push_back(std::move(metric));
}

}  // namespace

ServerMetrics::ServerMetrics()
    : buckets_{0.0001, 0.00025, 0.0005, 0.001, 0.0025, 0.005, 0.01, 0.025,
               0.05,   0.1,     0.25,   0.5,   1,      2.5,   5,    10},
      registry_(std::make_shared<prometheus::Registry>()),
      rpcs_(prometheus::BuildCounter()
                .Name("fleetnav_rpcs_total")
                .Help("RPCs finished, by full method name and status code")
                .Register(*registry_)),
      rpc_seconds_(prometheus::BuildHistogram()
                       .Name("fleetnav_rpc_duration_seconds")
                       .Help("Time from a call's arrival to its status, by method (streams: "
                             "their whole life)")
                       .Register(*registry_)),
      dispatch_seconds_(prometheus::BuildHistogram()
                            .Name("fleetnav_dispatch_pass_duration_seconds")
                            .Help("Dispatcher passes that assigned jobs: matching and the "
                                  "traffic plan replanned with the new jobs")
                            .Register(*registry_)
                            .Add({}, buckets_)),
      store_seconds_(prometheus::BuildHistogram()
                         .Name("fleetnav_store_transaction_duration_seconds")
                         .Help("SQLite transactions committed, lock wait and fsync included")
                         .Register(*registry_)
                         .Add({}, buckets_)) {}

void ServerMetrics::ObserveRpc(const std::string& method, grpc::StatusCode code, double seconds) {
  // gRPC's and absl's codes are the same numbers, so absl names them ("OK", "NOT_FOUND", ...).
  rpcs_
      .Add({{"method", method},
            {"code", absl::StatusCodeToString(static_cast<absl::StatusCode>(code))}})
      .Increment();
  rpc_seconds_.Add({{"method", method}}, buckets_).Observe(seconds);
}

void ServerMetrics::ObserveDispatchPass(double seconds) { dispatch_seconds_.Observe(seconds); }

void ServerMetrics::ObserveStoreTransaction(double seconds) { store_seconds_.Observe(seconds); }

std::unique_ptr<grpc::experimental::ServerInterceptorFactoryInterface>
ServerMetrics::InterceptorFactory() {
  return std::make_unique<RpcMetricsFactory>(this);
}

std::string ServerMetrics::Render(const FleetStateFigures& state) const {
  std::vector<prometheus::MetricFamily> families = registry_->Collect();
  prometheus::MetricFamily robots =
      Family("fleetnav_robots", "Robots known to the server, by connection state",
             prometheus::MetricType::Gauge);
  for (ConnectionState connection :
       {ConnectionState::kOnline, ConnectionState::kStale, ConnectionState::kOffline}) {
    const std::string name(ConnectionStateName(connection));
    const auto found = state.robots_by_state.find(name);
    AddSample(robots, "state", name,
              found == state.robots_by_state.end() ? 0.0 : static_cast<double>(found->second));
  }
  families.push_back(std::move(robots));
  prometheus::MetricFamily jobs =
      Family("fleetnav_jobs", "Jobs in the store, by state", prometheus::MetricType::Gauge);
  for (const auto& [job_state, count] : state.jobs_by_state) {
    AddSample(jobs, "state", job_state, static_cast<double>(count));
  }
  families.push_back(std::move(jobs));
  prometheus::MetricFamily telemetry =
      Family("fleetnav_telemetry_messages_total", "Robot telemetry messages accepted",
             prometheus::MetricType::Counter);
  AddSample(telemetry, "", "", static_cast<double>(state.telemetry_messages));
  families.push_back(std::move(telemetry));
  prometheus::MetricFamily access =
      Family("fleetnav_access_total",
             "Calls the TLS gate decided: admitted, unauthenticated (missing or bad "
             "credentials), denied (a role or robot id that may not)",
             prometheus::MetricType::Counter);
  AddSample(access, "outcome", "admitted", static_cast<double>(state.access.admitted));
  AddSample(access, "outcome", "unauthenticated",
            static_cast<double>(state.access.unauthenticated));
  AddSample(access, "outcome", "denied", static_cast<double>(state.access.denied));
  families.push_back(std::move(access));
  prometheus::MetricFamily handshakes =
      Family("fleetnav_tls_handshakes_refused_total",
             "TLS handshakes refused before any call: plaintext clients, client certificates "
             "of another CA, expired or not yet valid",
             prometheus::MetricType::Counter);
  AddSample(handshakes, "", "", static_cast<double>(state.access.handshakes_refused));
  families.push_back(std::move(handshakes));
  return prometheus::TextSerializer().Serialize(families);
}

}  // namespace fleetnav::server
