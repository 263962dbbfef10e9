#include "fleetnav/storage/memory/memory_fleet_repositories.hpp"

#include <algorithm>
#include <cstdlib>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "fleetnav/core/echo_input.hpp"

namespace fleetnav::storage {
namespace {

template <typename T>
absl::StatusOr<T> PickVersion(const std::vector<T>& versions, uint32_t version,
                              const std::string& what) {
  if (versions.empty()) return absl::NotFoundError(absl::StrCat(what, " not found"));
  if (version == 0) return versions.back();
  if (version > versions.size()) {
    return absl::NotFoundError(absl::StrCat(what, " has no version ", version));
  }
  return versions[version - 1];
}

// Appends `stored` as the next version of `key`'s series and returns that version.
template <typename T>
uint32_t AppendVersion(std::map<std::string, std::vector<T>>& series, const std::string& key,
                       T stored) {
  auto& versions = series[key];
  stored.version = static_cast<uint32_t>(versions.size() + 1);
  versions.push_back(std::move(stored));
  return versions.back().version;
}

// Forgets every version of `key`'s series; NotFound("`what` not found") when it has none.
template <typename T>
absl::Status EraseSeries(std::map<std::string, std::vector<T>>& series, const std::string& key,
                         const std::string& what) {
  auto it = series.find(key);
  if (it == series.end() || it->second.empty()) {
    return absl::NotFoundError(absl::StrCat(what, " not found"));
  }
  series.erase(it);
  return absl::OkStatus();
}

bool Matches(const Job& job, const JobFilter& filter) {
  if (!filter.states.empty() &&
      std::find(filter.states.begin(), filter.states.end(), job.state) == filter.states.end()) {
    return false;
  }
  if (!filter.robot_id.empty() && job.requested_robot_id != filter.robot_id &&
      job.assigned_robot_id != filter.robot_id) {
    return false;
  }
  return filter.map_id.empty() || job.map_id == filter.map_id;
}

}  // namespace

absl::StatusOr<uint32_t> MemoryMarkerSetRepository::PutMarkerSet(const MarkerSet& markers,
                                                                 int64_t created_unix_ms) {
  absl::MutexLock lock(&mutex_);
  return AppendVersion(sets_, markers.map_id, StoredMarkerSet{markers, 0, created_unix_ms});
}

absl::StatusOr<StoredMarkerSet> MemoryMarkerSetRepository::GetMarkerSet(const std::string& map_id,
                                                                        uint32_t version) {
  absl::MutexLock lock(&mutex_);
  return PickVersion(sets_[map_id], version,
                     absl::StrCat("marker set of map '", EchoInput(map_id), "'"));
}

absl::Status MemoryMarkerSetRepository::DeleteMarkerSet(const std::string& map_id) {
  absl::MutexLock lock(&mutex_);
  return EraseSeries(sets_, map_id, absl::StrCat("marker set of map '", EchoInput(map_id), "'"));
}

absl::StatusOr<uint32_t> MemoryZoneSetRepository::PutZoneSet(const ZoneSet& zones,
                                                             int64_t created_unix_ms) {
  absl::MutexLock lock(&mutex_);
  return AppendVersion(sets_, zones.map_id, StoredZoneSet{zones, 0, created_unix_ms});
}

absl::StatusOr<StoredZoneSet> MemoryZoneSetRepository::GetZoneSet(const std::string& map_id,
                                                                  uint32_t version) {
  absl::MutexLock lock(&mutex_);
  auto it = sets_.find(map_id);
  return PickVersion(it == sets_.end() ? std::vector<StoredZoneSet>{} : it->second, version,
                     absl::StrCat("zones of map '", EchoInput(map_id), "'"));
}

absl::StatusOr<std::vector<StoredZoneSet>> MemoryZoneSetRepository::ListZoneSets() {
  absl::MutexLock lock(&mutex_);
  std::vector<StoredZoneSet> out;
  for (const auto& [map_id, versions] : sets_) {
    if (!versions.empty()) out.push_back(versions.back());
  }
  return out;
}

absl::Status MemoryZoneSetRepository::DeleteZoneSet(const std::string& map_id) {
  absl::MutexLock lock(&mutex_);
  return EraseSeries(sets_, map_id, absl::StrCat("zones of map '", EchoInput(map_id), "'"));
}

absl::Status MemoryStopRepository::PutStop(const RobotStop& stop) {
  absl::MutexLock lock(&mutex_);
  for (const RobotStop& existing : stops_) {
    if (existing.map_id == stop.map_id && existing.zone == stop.zone) {
      return absl::AlreadyExistsError(
          absl::StrCat("a stop of ", EchoInput(stop.Describe()), " is already in force"));
    }
  }
  stops_.push_back(stop);
  return absl::OkStatus();
}

absl::Status MemoryStopRepository::DeleteStop(const std::string& map_id, const std::string& zone) {
  absl::MutexLock lock(&mutex_);
  const auto erased = std::erase_if(
      stops_, [&](const RobotStop& stop) { return stop.map_id == map_id && stop.zone == zone; });
  if (erased == 0) {
    RobotStop scope;
    scope.map_id = map_id;
    scope.zone = zone;
    return absl::NotFoundError(
        absl::StrCat("no stop of ", EchoInput(scope.Describe()), " is in force"));
  }
  return absl::OkStatus();
}

absl::StatusOr<std::vector<RobotStop>> MemoryStopRepository::ListStops() {
  absl::MutexLock lock(&mutex_);
  return stops_;
}

absl::StatusOr<uint32_t> MemoryRouteRepository::PutRoute(const Route& route,
                                                         int64_t created_unix_ms) {
  absl::MutexLock lock(&mutex_);
  auto& versions = routes_[route.name];
  const auto version = static_cast<uint32_t>(versions.size() + 1);
  versions.push_back(StoredRoute{route, version, created_unix_ms});
  return version;
}

absl::StatusOr<StoredRoute> MemoryRouteRepository::GetRoute(const std::string& name,
                                                            uint32_t version) {
  absl::MutexLock lock(&mutex_);
  return PickVersion(routes_[name], version, absl::StrCat("route '", EchoInput(name), "'"));
}

absl::StatusOr<std::vector<StoredRoute>> MemoryRouteRepository::ListRoutes(
    const std::string& map_id) {
  absl::MutexLock lock(&mutex_);
  std::vector<StoredRoute> out;
  for (const auto& [name, versions] : routes_) {
    if (!versions.empty() && (map_id.empty() || versions.back().route.map_id == map_id)) {
      out.push_back(versions.back());
    }
  }
  return out;
}

absl::StatusOr<int> MemoryRouteRepository::CountRoutesOnMap(const std::string& map_id) {
  absl::MutexLock lock(&mutex_);
  int count = 0;
  for (const auto& [name, versions] : routes_) {
    count += std::any_of(versions.begin(), versions.end(),
                         [&](const StoredRoute& r) { return r.route.map_id == map_id; });
  }
  return count;
}

absl::Status MemoryRouteRepository::DeleteRoute(const std::string& name) {
  absl::MutexLock lock(&mutex_);
  auto it = routes_.find(name);
  if (it == routes_.end() || it->second.empty()) {
    return absl::NotFoundError(absl::StrCat("route '", EchoInput(name), "' not found"));
  }
  routes_.erase(it);
  return absl::OkStatus();
}

absl::Status MemoryRobotRepository::UpsertRobot(const StoredRobot& robot) {
  absl::MutexLock lock(&mutex_);
  robots_[robot.robot_id] = robot;
  return absl::OkStatus();
}

absl::StatusOr<std::vector<StoredRobot>> MemoryRobotRepository::ListRobots() {
  absl::MutexLock lock(&mutex_);
  std::vector<StoredRobot> out;
  for (const auto& [id, robot] : robots_) out.push_back(robot);
  return out;
}

absl::Status MemoryRobotRepository::DeleteRobot(const std::string& robot_id) {
  absl::MutexLock lock(&mutex_);
  if (robots_.erase(robot_id) == 0) {
    return absl::NotFoundError(absl::StrCat("robot '", EchoInput(robot_id), "' not found"));
  }
  return absl::OkStatus();
}

absl::Status MemoryOperatorTokenRepository::InsertToken(const StoredOperatorToken& stored) {
  absl::MutexLock lock(&mutex_);
  for (const auto& [name, existing] : tokens_) {
    if (name == stored.token.name || existing.token.sha256_hex == stored.token.sha256_hex) {
      return absl::AlreadyExistsError(absl::StrCat("a token named '", EchoInput(stored.token.name),
                                                   "' or with the same secret exists"));
    }
  }
  tokens_[stored.token.name] = stored;
  return absl::OkStatus();
}

absl::StatusOr<std::vector<StoredOperatorToken>> MemoryOperatorTokenRepository::ListTokens() {
  absl::MutexLock lock(&mutex_);
  std::vector<StoredOperatorToken> out;
  for (const auto& [name, stored] : tokens_) out.push_back(stored);
  return out;
}

absl::Status MemoryOperatorTokenRepository::DeleteToken(const std::string& name) {
  absl::MutexLock lock(&mutex_);
  if (tokens_.erase(name) == 0) {
    return absl::NotFoundError(absl::StrCat("token '", EchoInput(name), "' not found"));
  }
  return absl::OkStatus();
}

absl::StatusOr<CreatedJob> MemoryJobRepository::CreateJob(Job job, JobEvent first_event) {
  absl::MutexLock lock(&mutex_);
  if (!job.idempotency_key.empty()) {
    for (const Job& existing : jobs_) {
      if (existing.idempotency_key == job.idempotency_key) return CreatedJob{existing, true};
    }
  }
  job.job_id = absl::StrFormat("job-%06d", jobs_.size() + 1);
  jobs_.push_back(job);
  first_event.job_id = job.job_id;
  first_event.sequence = 1;
  events_[job.job_id].push_back(first_event);
  return CreatedJob{job, false};
}

absl::StatusOr<Job> MemoryJobRepository::GetJob(const std::string& job_id) {
  absl::MutexLock lock(&mutex_);
  for (const Job& job : jobs_) {
    if (job.job_id == job_id) return job;
  }
  return absl::NotFoundError(absl::StrCat("job '", EchoInput(job_id), "' not found"));
}

absl::StatusOr<std::map<JobState, int64_t>> MemoryJobRepository::CountJobsByState() {
  absl::MutexLock lock(&mutex_);
  std::map<JobState, int64_t> counts;
  for (const Job& job : jobs_) ++counts[job.state];
  return counts;
}

absl::StatusOr<JobPage> MemoryJobRepository::ListJobs(const JobFilter& filter) {
  int64_t after_seq = 0;
  if (!filter.page_token.empty()) {
    char* end = nullptr;
    after_seq = std::strtoll(filter.page_token.c_str(), &end, 10);
    if (end == filter.page_token.c_str() || *end != '\0' || after_seq < 0) {
      return absl::InvalidArgumentError(absl::StrCat(
          "page_token: not a token this server issued: '", EchoInput(filter.page_token), "'"));
    }
  }
  absl::MutexLock lock(&mutex_);
  JobPage page;
  int64_t last_seq = after_seq;
  for (size_t i = static_cast<size_t>(after_seq); i < jobs_.size(); ++i) {
    if (!Matches(jobs_[i], filter)) continue;
    if (static_cast<int>(page.jobs.size()) == filter.page_size) {
      page.next_page_token = absl::StrCat(last_seq);
      break;
    }
    page.jobs.push_back(jobs_[i]);
    last_seq = static_cast<int64_t>(i + 1);
  }
  return page;
}

absl::StatusOr<int64_t> MemoryJobRepository::UpdateJob(const Job& job, JobEvent event) {
  absl::MutexLock lock(&mutex_);
  for (Job& stored : jobs_) {
    if (stored.job_id != job.job_id) continue;
    stored = job;
    auto& events = events_[job.job_id];
    event.job_id = job.job_id;
    event.sequence = static_cast<int64_t>(events.size() + 1);
    events.push_back(event);
    return event.sequence;
  }
  return absl::NotFoundError(absl::StrCat("job '", job.job_id, "' not found"));
}

absl::StatusOr<std::vector<JobEvent>> MemoryJobRepository::ListEvents(const std::string& job_id,
                                                                      int64_t after_sequence) {
  absl::MutexLock lock(&mutex_);
  std::vector<JobEvent> out;
  for (const JobEvent& event : events_[job_id]) {
    if (event.sequence > after_sequence) out.push_back(event);
  }
  return out;
}

absl::Status MemoryPoseHistoryRepository::AppendPoses(const std::vector<PoseSample>& samples) {
  absl::MutexLock lock(&mutex_);
  samples_.insert(samples_.end(), samples.begin(), samples.end());
  return absl::OkStatus();
}

absl::StatusOr<std::vector<PoseSample>> MemoryPoseHistoryRepository::ListPoses(
    const std::string& robot_id, int64_t since_unix_ms, int limit) {
  absl::MutexLock lock(&mutex_);
  std::vector<PoseSample> out;
  for (const PoseSample& sample : samples_) {
    if (static_cast<int>(out.size()) >= limit) break;
    if (sample.robot_id == robot_id && sample.unix_ms >= since_unix_ms) out.push_back(sample);
  }
  return out;
}

absl::StatusOr<int64_t> MemoryPoseHistoryRepository::PruneBefore(int64_t before_unix_ms) {
  absl::MutexLock lock(&mutex_);
  const size_t before = samples_.size();
  samples_.erase(std::remove_if(samples_.begin(), samples_.end(),
                                [&](const PoseSample& s) { return s.unix_ms < before_unix_ms; }),
                 samples_.end());
  return static_cast<int64_t>(before - samples_.size());
}

}  // namespace fleetnav::storage
