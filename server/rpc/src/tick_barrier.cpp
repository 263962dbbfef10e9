#include "fleetnav/server/rpc/tick_barrier.hpp"

namespace fleetnav::server {

uint64_t TickBarrier::Join(const std::string& robot_id, uint64_t from_tick, Handler handle,
                           Acknowledger acknowledge) {
  absl::MutexLock lock(&mutex_);
  if (!active_ && work_.first_join) work_.first_join();
  if (auto old = member_of_robot_.find(robot_id); old != member_of_robot_.end()) {
    if (auto it = members_.find(old->second); it != members_.end()) {
      TakeIn(&it->second);
      members_.erase(it);
    }
  }
  const uint64_t key = next_key_++;
  members_[key] =
      Member{robot_id, from_tick, std::move(handle), std::move(acknowledge), {}, std::nullopt};
  member_of_robot_[robot_id] = key;
  active_ = true;
  return key;
}

bool TickBarrier::Hold(uint64_t member, const v1::AgentMessage& message) {
  absl::MutexLock lock(&mutex_);
  auto it = members_.find(member);
  if (it == members_.end()) return false;
  it->second.held.push_back(message);
  return true;
}

void TickBarrier::EndTick(uint64_t member, const v1::TickDone& done) {
  absl::MutexLock lock(&mutex_);
  auto it = members_.find(member);
  if (it == members_.end()) return;
  it->second.done = done;
  RunReadyTicks();
}

void TickBarrier::Leave(uint64_t member) {
  absl::MutexLock lock(&mutex_);
  auto it = members_.find(member);
  if (it == members_.end()) return;
  TakeIn(&it->second);
  if (auto robot = member_of_robot_.find(it->second.robot_id);
      robot != member_of_robot_.end() && robot->second == member) {
    member_of_robot_.erase(robot);
  }
  members_.erase(it);
  RunReadyTicks();
}

bool TickBarrier::active() const {
  absl::MutexLock lock(&mutex_);
  return active_;
}

std::optional<uint64_t> TickBarrier::last_tick() const {
  absl::MutexLock lock(&mutex_);
  return last_tick_;
}

void TickBarrier::TakeIn(Member* member) {
  std::vector<v1::AgentMessage> held;
  held.swap(member->held);
  for (const v1::AgentMessage& message : held) member->handle(message);
}

void TickBarrier::RunReadyTicks() {
  // A stream that joined late (its agent was in the simulator's barrier before it reached the
  // server) may end a tick that already ran without it: it is taken in and acknowledged at
  // once, never waited for by the others.
  for (auto& [key, member] : members_) {
    if (member.done && last_tick_ && member.done->tick() <= *last_tick_) {
      const uint64_t late_tick = member.done->tick();
      TakeIn(&member);
      member.done.reset();
      member.acknowledge(late_tick);
    }
  }
  while (true) {
    // The earliest tick a member has ended.
    const v1::TickDone* earliest = nullptr;
    for (const auto& [key, member] : members_) {
      if (member.done && (earliest == nullptr || member.done->tick() < earliest->tick())) {
        earliest = &*member.done;
      }
    }
    if (earliest == nullptr) return;
    const uint64_t tick = earliest->tick();
    const int64_t sim_time_ns = earliest->sim_time_ns();
    // Every robot of the tick's barrier that has a stream here must have ended it, unless its
    // agent answered the tick before its stream took part (it joined meanwhile: waiting for it
    // would wait for ever, since the simulator waits for the others).
    for (const std::string& robot_id : earliest->lockstep_robot_ids()) {
      auto key = member_of_robot_.find(robot_id);
      if (key == member_of_robot_.end()) continue;  // no stream (a link cut, a restart)
      const Member& member = members_.at(key->second);
      if (tick < member.from_tick) continue;
      if (!member.done || member.done->tick() < tick) return;
    }
    if (work_.begin) work_.begin(sim_time_ns);
    // Robot by robot in id order (member_of_robot_ is sorted by id), whatever order the streams
    // delivered in; what a stream sent for a later tick waits for that tick.
    for (const auto& [robot_id, key] : member_of_robot_) {
      Member& member = members_.at(key);
      if (member.done && member.done->tick() == tick) TakeIn(&member);
    }
    if (work_.end) work_.end();
    last_tick_ = tick;
    for (const auto& [robot_id, key] : member_of_robot_) {
      Member& member = members_.at(key);
      if (member.done && member.done->tick() <= tick) {
        member.done.reset();
        member.acknowledge(tick);
      }
    }
  }
}

}  // namespace fleetnav::server
