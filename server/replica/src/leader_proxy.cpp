#include "fleetnav/server/replica/leader_proxy.hpp"

#include <grpcpp/support/client_callback.h>
#include <grpcpp/support/server_callback.h>

#include <chrono>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "fleetnav/proto/grpc_status.hpp"
#include "fleetnav/server/rpc/access_gate.hpp"
#include "fleetnav/server/rpc/replica_relay.hpp"

namespace fleetnav::server {
namespace {

/// A call refused before it reached any leader.
class RefusedCall final : public grpc::ServerGenericBidiReactor {
 public:
  explicit RefusedCall(grpc::Status status) { Finish(std::move(status)); }
  void OnDone() override { delete this; }
};

/// Request headers that belong to the hop, not to the call.
bool IsHopHeader(const std::string& key) {
  return key.empty() || key[0] == ':' || absl::StartsWith(key, "grpc-") || key == "te" ||
         key == "content-type" || key == "user-agent";
}

/// Headers only this replica may set on a relayed call: a caller's are dropped.
bool IsRelayHeader(const std::string& key) {
  return key == kRelayKeyHeader || key == kRelayedRobotHeader;
}

}  // namespace

/// One relayed call: the caller's side (a server reactor) and the leader's side (a client
/// reactor), as two objects because the two reactor interfaces share method names.
///
/// Two chains run at once, each with one operation in flight: caller → leader (read from the
/// caller, write to the leader, read again…) and leader → caller. The leader's side is kept
/// alive by two holds, one per chain, released when the chain can start nothing more on it,
/// so no operation is ever started on a finished client call. The leader's status ends the
/// caller's call; the caller cancelling cancels the leader's. Deleted when the caller's side
/// is done, which is always after the leader's side.
class ProxiedCall {
 public:
  ProxiedCall(LeaderProxy* proxy, grpc::GenericCallbackServerContext* context)
      : proxy_(proxy), context_(context), caller_(this), leader_(this) {}

  /// `relay_key` empty: relay no identity (plaintext).
  void Start(grpc::GenericStub* stub, const std::string& relay_key) {
    for (const auto& [key, value] : context_->client_metadata()) {
      const std::string name(key.data(), key.size());
      if (!IsHopHeader(name) && !IsRelayHeader(name)) {
        upstream_.AddMetadata(name, std::string(value.data(), value.size()));
      }
    }
    if (!relay_key.empty()) {
      upstream_.AddMetadata(kRelayKeyHeader, relay_key);
      // The robot CA verified this certificate in the handshake with the caller.
      const std::shared_ptr<const grpc::AuthContext> auth = context_->auth_context();
      const std::string robot_id = auth != nullptr ? CertificateIdentity(*auth) : "";
      if (!robot_id.empty()) upstream_.AddMetadata(kRelayedRobotHeader, robot_id);
    }
    if (context_->deadline() != std::chrono::system_clock::time_point::max()) {
      upstream_.set_deadline(context_->deadline());
    }
    stub->PrepareBidiStreamingCall(&upstream_, context_->method(), {}, &leader_);
    caller_.StartSendInitialMetadata();
    leader_.AddMultipleHolds(2);  // the two chains
    leader_.StartRead(&down_);
    leader_.StartCall();
    caller_.StartRead(&up_);
  }

  grpc::ServerGenericBidiReactor* caller() { return &caller_; }
  void Cancel() { upstream_.TryCancel(); }

 private:
  class CallerSide final : public grpc::ServerGenericBidiReactor {
   public:
    explicit CallerSide(ProxiedCall* call) : call_(call) {}
    void OnReadDone(bool ok) override { call_->CallerReadDone(ok); }
    void OnWriteDone(bool ok) override { call_->CallerWriteDone(ok); }
    void OnCancel() override { call_->upstream_.TryCancel(); }
    void OnDone() override { delete call_; }

   private:
    ProxiedCall* call_;
  };

  class LeaderSide final : public grpc::ClientBidiReactor<grpc::ByteBuffer, grpc::ByteBuffer> {
   public:
    explicit LeaderSide(ProxiedCall* call) : call_(call) {}
    void OnReadDone(bool ok) override { call_->LeaderReadDone(ok); }
    void OnWriteDone(bool ok) override { call_->LeaderWriteDone(ok); }
    void OnDone(const grpc::Status& status) override { call_->LeaderDone(status); }

   private:
    ProxiedCall* call_;
  };

  // Caller → leader.
  void CallerReadDone(bool ok) {
    enum { kNothing, kWrite, kWritesDone } next = kNothing;
    {
      absl::MutexLock lock(&mutex_);
      if (write_chain_ended_) return;  // the leader ended first
      if (ok) {
        leader_write_in_flight_ = true;
        next = kWrite;
      } else {
        write_chain_ended_ = true;
        next = kWritesDone;
      }
    }
    if (next == kWrite) {
      leader_.StartWrite(&up_);
    } else {
      leader_.StartWritesDone();
      leader_.RemoveHold();
    }
  }

  void LeaderWriteDone(bool ok) {
    bool read_more = false;
    {
      absl::MutexLock lock(&mutex_);
      leader_write_in_flight_ = false;
      // A leader that has already ended the stream (say, refused the hello this write carried)
      // waits for nothing more: reading on from a silent caller would hold its status forever.
      if (ok && !write_chain_ended_ && !leader_read_ended_) {
        read_more = true;
      } else {
        write_chain_ended_ = true;
      }
    }
    if (read_more) {
      caller_.StartRead(&up_);
    } else {
      leader_.RemoveHold();
    }
  }

  // Leader → caller.
  void LeaderReadDone(bool ok) {
    if (ok) {
      caller_.StartWrite(&down_);
      return;
    }
    // The leader sent its last message: its status follows. A caller that keeps its stream
    // open and silent must not hold that up, so the write chain ends here unless a write is in
    // flight (whose completion ends it).
    bool release_write_chain = false;
    {
      absl::MutexLock lock(&mutex_);
      leader_read_ended_ = true;
      if (!write_chain_ended_ && !leader_write_in_flight_) {
        write_chain_ended_ = true;
        release_write_chain = true;
      }
    }
    if (release_write_chain) leader_.RemoveHold();
    leader_.RemoveHold();  // the read chain
  }

  void CallerWriteDone(bool ok) {
    if (ok) {
      leader_.StartRead(&down_);
      return;
    }
    upstream_.TryCancel();  // the caller is gone
    leader_.RemoveHold();   // the read chain
  }

  void LeaderDone(const grpc::Status& status) {
    proxy_->Forget(this);
    for (const auto& [key, value] : upstream_.GetServerTrailingMetadata()) {
      const std::string name(key.data(), key.size());
      if (!IsHopHeader(name)) {
        context_->AddTrailingMetadata(name, std::string(value.data(), value.size()));
      }
    }
    caller_.Finish(status);
  }

  LeaderProxy* proxy_;
  grpc::GenericCallbackServerContext* context_;
  grpc::ClientContext upstream_;
  CallerSide caller_;
  LeaderSide leader_;
  grpc::ByteBuffer up_;    ///< the caller's message on its way to the leader
  grpc::ByteBuffer down_;  ///< the leader's message on its way to the caller
  absl::Mutex mutex_;
  bool write_chain_ended_ ABSL_GUARDED_BY(mutex_) = false;
  bool leader_write_in_flight_ ABSL_GUARDED_BY(mutex_) = false;
  bool leader_read_ended_ ABSL_GUARDED_BY(mutex_) = false;
};

LeaderProxy::~LeaderProxy() { Close(); }

void LeaderProxy::SetLeader(int64_t epoch, std::shared_ptr<grpc::Channel> channel) {
  absl::MutexLock lock(&mutex_);
  if (epoch != epoch_) {
    for (ProxiedCall* call : calls_) call->Cancel();
  }
  epoch_ = epoch;
  stub_ = channel != nullptr ? std::make_shared<grpc::GenericStub>(std::move(channel)) : nullptr;
}

void LeaderProxy::SetRelayKey(std::string relay_key) {
  absl::MutexLock lock(&mutex_);
  relay_key_ = std::move(relay_key);
}

void LeaderProxy::Close() {
  absl::MutexLock lock(&mutex_);
  closed_ = true;
  stub_.reset();
  for (ProxiedCall* call : calls_) call->Cancel();
}

grpc::ServerGenericBidiReactor* LeaderProxy::CreateReactor(
    grpc::GenericCallbackServerContext* context) {
  std::shared_ptr<grpc::GenericStub> stub;
  std::string relay_key;
  auto* call = new ProxiedCall(this, context);
  {
    absl::MutexLock lock(&mutex_);
    std::string refusal;
    if (closed_) {
      refusal = "shutting down";
    } else if (stub_ == nullptr) {
      refusal = epoch_ == 0 ? "no leader for this site yet; retry"
                            : absl::StrCat("the site's leader (epoch ", epoch_,
                                           ") is starting and cannot be reached yet; retry");
    }
    if (!refusal.empty()) {
      delete call;
      return new RefusedCall(ToGrpcStatus(absl::UnavailableError(refusal)));
    }
    stub = stub_;
    relay_key = relay_key_;
    calls_.insert(call);  // from here on a leader change cancels it
  }
  // Outside the lock: the call's reactions take it (Forget).
  call->Start(stub.get(), relay_key);
  return call->caller();
}

void LeaderProxy::Forget(ProxiedCall* call) {
  absl::MutexLock lock(&mutex_);
  calls_.erase(call);
}

}  // namespace fleetnav::server
