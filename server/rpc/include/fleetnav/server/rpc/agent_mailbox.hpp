#pragma once

#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "absl/synchronization/mutex.h"
#include "fleetnav/server/robots/robot_mailbox.hpp"
#include "fleetnav/v1/agent_service.pb.h"

namespace fleetnav::server {

/// The queue of server messages for one open agent stream. The stream registers a listener
/// that Push() calls (outside the lock) so it can start its next write. Thread-safe.
class AgentOutbox {
 public:
  explicit AgentOutbox(std::function<void()> on_push = nullptr) : on_push_(std::move(on_push)) {}
  void Push(v1::ServerMessage message);
  /// The oldest queued message, or nullopt when none is queued.
  std::optional<v1::ServerMessage> TryPop();
  /// Refuses further pushes and waits until no listener call is running, so the listener's
  /// owner may go away afterwards. Must not be called from the listener.
  void Close();

 private:
  const std::function<void()> on_push_;
  absl::Mutex mutex_;
  std::deque<v1::ServerMessage> queue_ ABSL_GUARDED_BY(mutex_);
  bool closed_ ABSL_GUARDED_BY(mutex_) = false;
  int listeners_running_ ABSL_GUARDED_BY(mutex_) = 0;
};

/// RobotMailbox over the open AgentService streams: one outbox per connected robot, replaced
/// when the robot connects again. Thread-safe; sends never block.
class AgentMailbox final : public RobotMailbox {
 public:
  /// Opens the robot's outbox (closing a previous one); `on_push` runs after each Push.
  std::shared_ptr<AgentOutbox> Open(const std::string& robot_id, std::function<void()> on_push);
  /// Removes the robot's outbox if it is still `outbox`, and closes it.
  void Close(const std::string& robot_id, const std::shared_ptr<AgentOutbox>& outbox);

  bool SendAssignment(const std::string& robot_id, const JobAssignment& assignment) override;
  bool SendCommand(const std::string& robot_id, const JobCommand& command) override;
  bool SendClearance(const std::string& robot_id, const ClearanceNotice& clearance) override;
  void BroadcastStops(const std::vector<RobotStop>& stops) override;
  void BroadcastZones(uint32_t version, const ZoneSet& zones) override;
  void BroadcastMapUpdate(const std::string& map_id, uint32_t map_version,
                          uint32_t marker_set_version) override;

 private:
  bool Send(const std::string& robot_id, v1::ServerMessage message);

  absl::Mutex mutex_;
  std::map<std::string, std::shared_ptr<AgentOutbox>> outboxes_ ABSL_GUARDED_BY(mutex_);
};

}  // namespace fleetnav::server
