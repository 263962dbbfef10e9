#pragma once

#include <grpcpp/channel.h>
#include <grpcpp/generic/async_generic_service.h>
#include <grpcpp/generic/generic_stub.h>

#include <cstdint>
#include <memory>
#include <set>
#include <string>

#include "absl/synchronization/mutex.h"

namespace fleetnav::server {

class ProxiedCall;

/// Forwards every call a replica's public port receives to the site's leader, byte for byte:
/// a gRPC generic service, so one bidirectional relay serves unary calls, WatchFleet and the
/// robots' AgentService streams alike, with the caller's metadata (its token) and deadline.
/// Messages flow as they come in both directions, one in flight each way, so a slow reader
/// holds its writer back instead of filling memory. When the leader changes, calls still
/// relayed to the old one are cancelled, so robots reconnect and reach the new leader; while no
/// leader is known calls fail UNAVAILABLE, which clients retry. With a relay key (replicas
/// serving TLS) it tells the leader who the caller proved to be: each relayed call carries the
/// key and the robot id of the client certificate verified on the caller's connection, if any
/// (replica_relay.hpp); the same headers sent by a caller are dropped, never passed on.
/// Thread-safe.
class LeaderProxy final : public grpc::CallbackGenericService {
 public:
  LeaderProxy() = default;
  ~LeaderProxy() override;
  LeaderProxy(const LeaderProxy&) = delete;
  LeaderProxy& operator=(const LeaderProxy&) = delete;

  /// The leader at `epoch`, reached through `channel` (null: the leader is starting and cannot
  /// be reached yet). Calls relayed to a leader of an earlier epoch are cancelled.
  void SetLeader(int64_t epoch, std::shared_ptr<grpc::Channel> channel);
  /// Relays the callers' verified robot ids with `relay_key` from the next call on (empty:
  /// relay none, as over plaintext).
  void SetRelayKey(std::string relay_key);
  /// Cancels every call in flight and refuses new ones (before the server shuts down).
  void Close();

  grpc::ServerGenericBidiReactor* CreateReactor(
      grpc::GenericCallbackServerContext* context) override;

 private:
  friend class ProxiedCall;
  void Forget(ProxiedCall* call);

  absl::Mutex mutex_;
  int64_t epoch_ ABSL_GUARDED_BY(mutex_) = 0;
  std::shared_ptr<grpc::GenericStub> stub_ ABSL_GUARDED_BY(mutex_);
  std::string relay_key_ ABSL_GUARDED_BY(mutex_);
  bool closed_ ABSL_GUARDED_BY(mutex_) = false;
  std::set<ProxiedCall*> calls_ ABSL_GUARDED_BY(mutex_);
};

}  // namespace fleetnav::server
