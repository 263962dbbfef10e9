#pragma once

#include <deque>
#include <map>
#include <memory>
#include <string>

#include "absl/synchronization/mutex.h"
#include "fleetnav/server/robot_mailbox.hpp"
#include "fleetnav/v1/agent_service.pb.h"

namespace fleetnav::server {

/// The queue of server messages for one open agent stream, drained by that stream's writer.
/// Thread-safe.
class AgentOutbox {
 public:
  void Push(v1::ServerMessage message);
  /// Blocks until a message is queued or the outbox is closed (then nullopt).
  std::optional<v1::ServerMessage> Pop();
  void Close();

 private:
  absl::Mutex mutex_;
  std::deque<v1::ServerMessage> queue_ ABSL_GUARDED_BY(mutex_);
  bool closed_ ABSL_GUARDED_BY(mutex_) = false;
};

/// RobotMailbox over the open AgentService streams: one outbox per connected robot, replaced
/// when the robot connects again. Thread-safe; sends never block.
class AgentMailbox final : public RobotMailbox {
 public:
  std::shared_ptr<AgentOutbox> Open(const std::string& robot_id);
  /// Removes the robot's outbox if it is still `outbox`, and closes it.
  void Close(const std::string& robot_id, const std::shared_ptr<AgentOutbox>& outbox);

  bool SendAssignment(const std::string& robot_id, const Assignment& assignment) override;
  bool SendCommand(const std::string& robot_id, RobotCommandType type, const std::string& job_id,
                   const std::string& reason) override;

 private:
  bool Send(const std::string& robot_id, v1::ServerMessage message);

  absl::Mutex mutex_;
  std::map<std::string, std::shared_ptr<AgentOutbox>> outboxes_ ABSL_GUARDED_BY(mutex_);
};

}  // namespace fleetnav::server
