#pragma once

#include <map>
#include <vector>

#include "absl/synchronization/mutex.h"
#include "fleetnav/storage/job_repository.hpp"
#include "fleetnav/storage/marker_set_repository.hpp"
#include "fleetnav/storage/operator_token_repository.hpp"
#include "fleetnav/storage/pose_history_repository.hpp"
#include "fleetnav/storage/robot_repository.hpp"
#include "fleetnav/storage/route_repository.hpp"
#include "fleetnav/storage/stop_repository.hpp"
#include "fleetnav/storage/zone_set_repository.hpp"

namespace fleetnav::storage {

/// MarkerSetRepository in memory, for unit tests of the layers above. Thread-safe.
class MemoryMarkerSetRepository final : public MarkerSetRepository {
 public:
  absl::StatusOr<uint32_t> PutMarkerSet(const MarkerSet& markers, int64_t created_unix_ms) override;
  absl::StatusOr<StoredMarkerSet> GetMarkerSet(const std::string& map_id,
                                               uint32_t version) override;
  absl::Status DeleteMarkerSet(const std::string& map_id) override;

 private:
  absl::Mutex mutex_;
  std::map<std::string, std::vector<StoredMarkerSet>> sets_ ABSL_GUARDED_BY(mutex_);
};

/// ZoneSetRepository in memory, for unit tests of the layers above. Thread-safe.
class MemoryZoneSetRepository final : public ZoneSetRepository {
 public:
  absl::StatusOr<uint32_t> PutZoneSet(const ZoneSet& zones, int64_t created_unix_ms) override;
  absl::StatusOr<StoredZoneSet> GetZoneSet(const std::string& map_id, uint32_t version) override;
  absl::StatusOr<std::vector<StoredZoneSet>> ListZoneSets() override;
  absl::Status DeleteZoneSet(const std::string& map_id) override;

 private:
  absl::Mutex mutex_;
  std::map<std::string, std::vector<StoredZoneSet>> sets_ ABSL_GUARDED_BY(mutex_);
};

/// StopRepository in memory, for unit tests of the layers above. Thread-safe.
class MemoryStopRepository final : public StopRepository {
 public:
  absl::Status PutStop(const RobotStop& stop) override;
  absl::Status DeleteStop(const std::string& map_id, const std::string& zone) override;
  absl::StatusOr<std::vector<RobotStop>> ListStops() override;

 private:
  absl::Mutex mutex_;
  std::vector<RobotStop> stops_ ABSL_GUARDED_BY(mutex_);  ///< in the order they were made
};

/// RouteRepository in memory, for unit tests of the layers above. Thread-safe.
class MemoryRouteRepository final : public RouteRepository {
 public:
  absl::StatusOr<uint32_t> PutRoute(const Route& route, int64_t created_unix_ms) override;
  absl::StatusOr<StoredRoute> GetRoute(const std::string& name, uint32_t version) override;
  absl::StatusOr<std::vector<StoredRoute>> ListRoutes(const std::string& map_id) override;
  absl::StatusOr<int> CountRoutesOnMap(const std::string& map_id) override;
  absl::Status DeleteRoute(const std::string& name) override;

 private:
  absl::Mutex mutex_;
  std::map<std::string, std::vector<StoredRoute>> routes_ ABSL_GUARDED_BY(mutex_);
};

/// RobotRepository in memory. Thread-safe.
class MemoryRobotRepository final : public RobotRepository {
 public:
  absl::Status UpsertRobot(const StoredRobot& robot) override;
  absl::StatusOr<std::vector<StoredRobot>> ListRobots() override;
  absl::Status DeleteRobot(const std::string& robot_id) override;

 private:
  absl::Mutex mutex_;
  std::map<std::string, StoredRobot> robots_ ABSL_GUARDED_BY(mutex_);
};

/// OperatorTokenRepository in memory, with SQLite's rules (name and hash unique). Thread-safe.
class MemoryOperatorTokenRepository final : public OperatorTokenRepository {
 public:
  absl::Status InsertToken(const StoredOperatorToken& stored) override;
  absl::StatusOr<std::vector<StoredOperatorToken>> ListTokens() override;
  absl::Status DeleteToken(const std::string& name) override;

 private:
  absl::Mutex mutex_;
  std::map<std::string, StoredOperatorToken> tokens_ ABSL_GUARDED_BY(mutex_);  ///< by name
};

/// JobRepository in memory, with the same id, idempotency and paging rules as SQLite.
/// Thread-safe.
class MemoryJobRepository final : public JobRepository {
 public:
  absl::StatusOr<CreatedJob> CreateJob(Job job, JobEvent first_event) override;
  absl::StatusOr<Job> GetJob(const std::string& job_id) override;
  absl::StatusOr<JobPage> ListJobs(const JobFilter& filter) override;
  absl::StatusOr<std::map<JobState, int64_t>> CountJobsByState() override;
  absl::StatusOr<int64_t> UpdateJob(const Job& job, JobEvent event) override;
  absl::StatusOr<std::vector<JobEvent>> ListEvents(const std::string& job_id,
                                                   int64_t after_sequence) override;

 private:
  absl::Mutex mutex_;
  std::vector<Job> jobs_ ABSL_GUARDED_BY(mutex_);  ///< index = seq - 1
  std::map<std::string, std::vector<JobEvent>> events_ ABSL_GUARDED_BY(mutex_);
};

/// PoseHistoryRepository in memory. Thread-safe.
class MemoryPoseHistoryRepository final : public PoseHistoryRepository {
 public:
  absl::Status AppendPoses(const std::vector<PoseSample>& samples) override;
  absl::StatusOr<std::vector<PoseSample>> ListPoses(const std::string& robot_id,
                                                    int64_t since_unix_ms, int limit) override;
  absl::StatusOr<int64_t> PruneBefore(int64_t before_unix_ms) override;

 private:
  absl::Mutex mutex_;
  std::vector<PoseSample> samples_ ABSL_GUARDED_BY(mutex_);
};

}  // namespace fleetnav::storage
