#include "fleetnav/server/robots/fleet_registry.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/echo_input.hpp"

namespace fleetnav::server {

absl::Status FleetRegistryParams::Validate() const {
  if (!std::isfinite(stale_after_s) || stale_after_s <= 0.0) {
    return absl::InvalidArgumentError(
        absl::StrCat("stale_after_s must be finite and > 0, got ", stale_after_s));
  }
  return absl::OkStatus();
}

FleetRegistry::FleetRegistry(const Clock* clock, FleetRegistryParams params)
    : clock_(clock), params_(params) {}

FleetRegistry::Entry* FleetRegistry::Find(const std::string& robot_id) {
  auto it = index_.find(robot_id);
  return it == index_.end() ? nullptr : it->second;
}

const FleetRegistry::Entry* FleetRegistry::Find(const std::string& robot_id) const {
  auto it = index_.find(robot_id);
  return it == index_.end() ? nullptr : it->second;
}

FleetRegistry::Entry& FleetRegistry::Insert(const std::string& robot_id) {
  Entry*& slot = index_[robot_id];
  if (slot == nullptr) slot = &robots_[robot_id];
  return *slot;
}

uint64_t FleetRegistry::Connect(const RobotIdentity& identity) {
  absl::MutexLock lock(&mutex_);
  Entry& entry = Insert(identity.robot_id);
  entry.session = next_session_++;
  entry.record.identity = identity;
  entry.record.connection = ConnectionState::kOnline;
  entry.record.last_seen_ns = clock_->NowNs();
  entry.record.revision = NextRevision();
  return entry.session;
}

absl::Status FleetRegistry::CheckSessionLocked(const std::string& robot_id,
                                               uint64_t session) const {
  const Entry* found = Find(robot_id);
  if (found == nullptr) {
    return absl::NotFoundError(absl::StrCat("robot '", EchoInput(robot_id), "' is not registered"));
  }
  if (found->session != session) {
    return absl::FailedPreconditionError(absl::StrCat(
        "robot '", EchoInput(robot_id), "' connected again; this stream was replaced"));
  }
  return absl::OkStatus();
}

absl::Status FleetRegistry::CheckSession(const std::string& robot_id, uint64_t session) const {
  absl::MutexLock lock(&mutex_);
  return CheckSessionLocked(robot_id, session);
}

absl::Status FleetRegistry::RecordTelemetry(const std::string& robot_id, uint64_t session,
                                            const Telemetry& telemetry) {
  absl::MutexLock lock(&mutex_);
  if (absl::Status s = CheckSessionLocked(robot_id, session); !s.ok()) return s;
  Entry& entry = *Find(robot_id);
  const int64_t now_ns = clock_->NowNs();
  if (!entry.record.traffic_wait.empty() && telemetry.mode == NavigationMode::kIdle) {
    entry.record.traffic_held_s +=
        static_cast<double>(std::max<int64_t>(0, now_ns - entry.record.last_seen_ns)) * 1e-9;
  }
  entry.record.last_telemetry = telemetry;
  entry.record.last_seen_ns = now_ns;
  entry.record.connection = ConnectionState::kOnline;
  ++entry.record.telemetry_count;
  entry.record.revision = NextRevision();
  return absl::OkStatus();
}

bool FleetRegistry::Disconnect(const std::string& robot_id, uint64_t session) {
  absl::MutexLock lock(&mutex_);
  Entry* entry = Find(robot_id);
  if (entry == nullptr || entry->session != session) return false;
  entry->record.connection = ConnectionState::kOffline;
  entry->offline_since_ns = clock_->NowNs();
  entry->record.revision = NextRevision();
  return true;
}

RobotRecord FleetRegistry::WithConnectionState(const Entry& entry) const {
  RobotRecord record = entry.record;
  if (record.connection == ConnectionState::kOnline) {
    const double silent_s = static_cast<double>(clock_->NowNs() - record.last_seen_ns) * 1e-9;
    if (silent_s > params_.stale_after_s) record.connection = ConnectionState::kStale;
  }
  return record;
}

void FleetRegistry::RestoreOffline(const RobotIdentity& identity) {
  absl::MutexLock lock(&mutex_);
  if (Find(identity.robot_id) != nullptr) return;
  Entry& entry = Insert(identity.robot_id);
  entry.record.identity = identity;
  entry.record.connection = ConnectionState::kOffline;
  entry.offline_since_ns = clock_->NowNs();
  entry.record.revision = NextRevision();
}

absl::Status FleetRegistry::Forget(const std::string& robot_id) {
  absl::MutexLock lock(&mutex_);
  const Entry* entry = Find(robot_id);
  if (entry == nullptr) {
    return absl::NotFoundError(absl::StrCat("robot '", EchoInput(robot_id), "' not found"));
  }
  if (entry->record.connection != ConnectionState::kOffline) {
    return absl::FailedPreconditionError(
        absl::StrCat("robot '", robot_id, "' is connected; it can be forgotten once offline"));
  }
  if (!entry->record.current_job_id.empty()) {
    return absl::FailedPreconditionError(absl::StrCat(
        "robot '", robot_id, "' holds job ", entry->record.current_job_id, "; cancel it first"));
  }
  index_.erase(robot_id);
  robots_.erase(robot_id);
  ++removals_;
  NextRevision();
  return absl::OkStatus();
}

std::vector<std::string> FleetRegistry::OfflineLongerThan(double offline_for_s) const {
  absl::ReaderMutexLock lock(&mutex_);
  const int64_t now_ns = clock_->NowNs();
  std::vector<std::string> out;
  for (const auto& [id, entry] : robots_) {
    if (entry.record.connection != ConnectionState::kOffline ||
        !entry.record.current_job_id.empty()) {
      continue;
    }
    if (static_cast<double>(now_ns - entry.offline_since_ns) * 1e-9 > offline_for_s) {
      out.push_back(id);
    }
  }
  return out;
}

uint64_t FleetRegistry::NextRevision() {
  ++revision_;
  if (listener_) listener_();
  return revision_;
}

uint64_t FleetRegistry::revision() const {
  absl::ReaderMutexLock lock(&mutex_);
  return revision_;
}

void FleetRegistry::RefreshStale() {
  absl::MutexLock lock(&mutex_);
  const int64_t now_ns = clock_->NowNs();
  for (auto& [id, entry] : robots_) {
    const bool stale =
        entry.record.connection == ConnectionState::kOnline &&
        static_cast<double>(now_ns - entry.record.last_seen_ns) * 1e-9 > params_.stale_after_s;
    if (stale == entry.shown_stale) continue;
    entry.shown_stale = stale;
    entry.record.revision = NextRevision();
  }
}

void FleetRegistry::SetChangeListener(std::function<void()> listener) {
  absl::MutexLock lock(&mutex_);
  listener_ = std::move(listener);
}

uint64_t FleetRegistry::removals() const {
  absl::ReaderMutexLock lock(&mutex_);
  return removals_;
}

void FleetRegistry::SetCurrentJob(const std::string& robot_id, const std::string& job_id) {
  absl::MutexLock lock(&mutex_);
  Entry* entry = Find(robot_id);
  if (entry == nullptr) return;
  entry->record.current_job_id = job_id;
  entry->record.revision = NextRevision();
}

void FleetRegistry::SetTrafficWait(const std::string& robot_id, const std::string& reason) {
  absl::MutexLock lock(&mutex_);
  Entry* entry = Find(robot_id);
  if (entry == nullptr || entry->record.traffic_wait == reason) return;
  entry->record.traffic_wait = reason;
  entry->record.revision = NextRevision();
}

absl::StatusOr<RobotRecord> FleetRegistry::Get(const std::string& robot_id) const {
  absl::ReaderMutexLock lock(&mutex_);
  const Entry* entry = Find(robot_id);
  if (entry == nullptr)
    return absl::NotFoundError(absl::StrCat("robot '", EchoInput(robot_id), "' not found"));
  return WithConnectionState(*entry);
}

std::vector<RobotRecord> FleetRegistry::Snapshot() const {
  absl::ReaderMutexLock lock(&mutex_);
  std::vector<RobotRecord> out;
  out.reserve(robots_.size());
  for (const auto& [id, entry] : robots_) out.push_back(WithConnectionState(entry));
  return out;
}

std::vector<RobotRecord> FleetRegistry::IdleOnline(
    const std::function<bool(const RobotRecord&)>& wanted) const {
  absl::ReaderMutexLock lock(&mutex_);
  const int64_t now_ns = clock_->NowNs();
  std::vector<RobotRecord> out;
  for (const auto& [id, entry] : robots_) {
    const RobotRecord& record = entry.record;
    if (record.connection != ConnectionState::kOnline || !record.current_job_id.empty()) continue;
    if (static_cast<double>(now_ns - record.last_seen_ns) * 1e-9 > params_.stale_after_s) continue;
    if (wanted(record)) out.push_back(record);
  }
  return out;
}

std::set<std::string> FleetRegistry::OnlineCapabilities() const {
  absl::ReaderMutexLock lock(&mutex_);
  std::set<std::string> out;
  for (const auto& [id, entry] : robots_) {
    if (entry.record.connection != ConnectionState::kOnline) continue;
    out.insert(entry.record.identity.capabilities.begin(),
               entry.record.identity.capabilities.end());
  }
  return out;
}

std::set<std::string> FleetRegistry::KnownCapabilities() const {
  absl::ReaderMutexLock lock(&mutex_);
  std::set<std::string> out;
  for (const auto& [id, entry] : robots_) {
    out.insert(entry.record.identity.capabilities.begin(),
               entry.record.identity.capabilities.end());
  }
  return out;
}

std::vector<RobotRecord> FleetRegistry::ChangedSince(uint64_t after_revision,
                                                     uint64_t* latest_revision) const {
  absl::ReaderMutexLock lock(&mutex_);
  std::vector<RobotRecord> out;
  for (const auto& [id, entry] : robots_) {
    if (entry.record.revision > after_revision) out.push_back(WithConnectionState(entry));
  }
  *latest_revision = revision_;
  return out;
}

}  // namespace fleetnav::server
