#pragma once

#include <grpcpp/support/server_interceptor.h>
#include <prometheus/counter.h>
#include <prometheus/family.h>
#include <prometheus/histogram.h>
#include <prometheus/registry.h>

#include <cstdint>
#include <map>
#include <memory>
#include <string>

#include "fleetnav/server/rpc/access_gate.hpp"

namespace fleetnav::server {

/// The server's state at a scrape, for the gauges (robots by connection state, jobs by state)
/// and the counters kept elsewhere.
struct FleetStateFigures {
  std::map<std::string, int64_t> robots_by_state;  ///< "online", "stale", "offline"
  std::map<std::string, int64_t> jobs_by_state;    ///< JobStateName
  uint64_t telemetry_messages = 0;
  AccessCounts access;
};

/// fleetnavd's Prometheus metrics (docs/metrics.md). Event-driven ones are observed where they
/// happen: every RPC by method and status code with its latency (a gRPC server interceptor, so
/// every service, unary and streaming, is counted the same way), each assigning dispatcher
/// pass, each store transaction. The rest is read from the server at scrape time
/// (FleetStateFigures). Render() writes Prometheus's text exposition format. Thread-safe.
class ServerMetrics {
 public:
  ServerMetrics();
  ServerMetrics(const ServerMetrics&) = delete;
  ServerMetrics& operator=(const ServerMetrics&) = delete;

  void ObserveRpc(const std::string& method, grpc::StatusCode code, double seconds);
  void ObserveDispatchPass(double seconds);
  void ObserveStoreTransaction(double seconds);

  /// What ServerBuilder needs to count every call.
  std::unique_ptr<grpc::experimental::ServerInterceptorFactoryInterface> InterceptorFactory();

  std::string Render(const FleetStateFigures& state) const;

 private:
  const prometheus::Histogram::BucketBoundaries buckets_;  ///< seconds, 100 µs to 10 s
  std::shared_ptr<prometheus::Registry> registry_;
  prometheus::Family<prometheus::Counter>& rpcs_;
  prometheus::Family<prometheus::Histogram>& rpc_seconds_;
  prometheus::Histogram& dispatch_seconds_;
  prometheus::Histogram& store_seconds_;
};

}  // namespace fleetnav::server
