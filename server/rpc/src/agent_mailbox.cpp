#include "fleetnav/server/rpc/agent_mailbox.hpp"

#include <algorithm>
#include <vector>

#include "fleetnav/proto/assignment_convert.hpp"
#include "fleetnav/proto/geometry_convert.hpp"
#include "fleetnav/proto/job_convert.hpp"
#include "fleetnav/proto/route_convert.hpp"
#include "fleetnav/proto/zone_convert.hpp"

namespace fleetnav::server {

void AgentOutbox::Push(v1::ServerMessage message) {
  {
    absl::MutexLock lock(&mutex_);
    if (closed_) return;
    queue_.push_back(std::move(message));
    if (!on_push_) return;
    ++listeners_running_;
  }
  on_push_();
  absl::MutexLock lock(&mutex_);
  --listeners_running_;
}

std::optional<v1::ServerMessage> AgentOutbox::TryPop() {
  absl::MutexLock lock(&mutex_);
  if (queue_.empty()) return std::nullopt;
  v1::ServerMessage message = std::move(queue_.front());
  queue_.pop_front();
  return message;
}

void AgentOutbox::Close() {
  absl::MutexLock lock(&mutex_);
  closed_ = true;
  auto idle = [this]() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_) { return listeners_running_ == 0; };
  mutex_.Await(absl::Condition(&idle));
}

std::shared_ptr<AgentOutbox> AgentMailbox::Open(const std::string& robot_id,
                                                std::function<void()> on_push) {
  auto outbox = std::make_shared<AgentOutbox>(std::move(on_push));
  absl::MutexLock lock(&mutex_);
  auto& slot = outboxes_[robot_id];
  if (slot != nullptr) slot->Close();
  slot = outbox;
  return outbox;
}

void AgentMailbox::Close(const std::string& robot_id, const std::shared_ptr<AgentOutbox>& outbox) {
  outbox->Close();
  absl::MutexLock lock(&mutex_);
  auto it = outboxes_.find(robot_id);
  if (it != outboxes_.end() && it->second == outbox) outboxes_.erase(it);
}

bool AgentMailbox::Send(const std::string& robot_id, v1::ServerMessage message) {
  std::shared_ptr<AgentOutbox> outbox;
  {
    absl::MutexLock lock(&mutex_);
    auto it = outboxes_.find(robot_id);
    if (it == outboxes_.end()) return false;
    outbox = it->second;
  }
  outbox->Push(std::move(message));
  return true;
}

bool AgentMailbox::SendAssignment(const std::string& robot_id, const JobAssignment& assignment) {
  v1::ServerMessage message;
  *message.mutable_assignment() = ToProto(assignment);
  return Send(robot_id, std::move(message));
}

bool AgentMailbox::SendCommand(const std::string& robot_id, const JobCommand& command) {
  v1::ServerMessage message;
  *message.mutable_command() = ToProto(command);
  return Send(robot_id, std::move(message));
}

bool AgentMailbox::SendClearance(const std::string& robot_id, const ClearanceNotice& clearance) {
  v1::ServerMessage message;
  *message.mutable_clearance() = ToProto(clearance);
  return Send(robot_id, std::move(message));
}

namespace {

v1::ServerMessage StopsMessage(const std::vector<RobotStop>& stops) {
  v1::ServerMessage message;
  // Set even when empty: "no stops in force" is news too.
  v1::StopUpdate* update = message.mutable_stops();
  for (const RobotStop& stop : stops) *update->add_stops() = ToProto(stop);
  return message;
}

}  // namespace

void AgentMailbox::BroadcastStops(const std::vector<RobotStop>& stops) {
  std::vector<std::shared_ptr<AgentOutbox>> outboxes;
  {
    absl::MutexLock lock(&mutex_);
    for (const auto& [robot, outbox] : outboxes_) outboxes.push_back(outbox);
  }
  const v1::ServerMessage message = StopsMessage(stops);
  for (const auto& outbox : outboxes) outbox->Push(message);
}

void AgentMailbox::BroadcastZones(uint32_t version, const ZoneSet& zones) {
  std::vector<std::shared_ptr<AgentOutbox>> outboxes;
  {
    absl::MutexLock lock(&mutex_);
    for (const auto& [robot, outbox] : outboxes_) outboxes.push_back(outbox);
  }
  v1::ServerMessage message;
  message.mutable_zones()->set_version(version);
  *message.mutable_zones()->mutable_zones() = ToProto(zones);
  for (const auto& outbox : outboxes) outbox->Push(message);
}

void AgentMailbox::BroadcastMapUpdate(const std::string& map_id, uint32_t map_version,
                                      uint32_t marker_set_version) {
  std::vector<std::shared_ptr<AgentOutbox>> outboxes;
  {
    absl::MutexLock lock(&mutex_);
    for (const auto& [robot, outbox] : outboxes_) outboxes.push_back(outbox);
  }
  v1::ServerMessage message;
  message.mutable_map_update()->set_map_id(map_id);
  message.mutable_map_update()->set_map_version(map_version);
  message.mutable_map_update()->set_marker_set_version(marker_set_version);
  for (const auto& outbox : outboxes) outbox->Push(message);
}

}  // namespace fleetnav::server
