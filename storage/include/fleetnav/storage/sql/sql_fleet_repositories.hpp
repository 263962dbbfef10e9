#pragma once

#include "fleetnav/storage/job_repository.hpp"
#include "fleetnav/storage/marker_set_repository.hpp"
#include "fleetnav/storage/operator_token_repository.hpp"
#include "fleetnav/storage/pose_history_repository.hpp"
#include "fleetnav/storage/robot_repository.hpp"
#include "fleetnav/storage/route_repository.hpp"
#include "fleetnav/storage/sql/sql_database.hpp"
#include "fleetnav/storage/stop_repository.hpp"
#include "fleetnav/storage/zone_set_repository.hpp"

namespace fleetnav::storage {

/// Marker sets on an SqlDatabase (SQLite or PostgreSQL), each version stored as the thesis's marker
/// YAML. Thread-safe.
class SqlMarkerSetRepository final : public MarkerSetRepository {
 public:
  explicit SqlMarkerSetRepository(SqlDatabase* db) : db_(db) {}
  absl::StatusOr<uint32_t> PutMarkerSet(const MarkerSet& markers, int64_t created_unix_ms) override;
  absl::StatusOr<StoredMarkerSet> GetMarkerSet(const std::string& map_id,
                                               uint32_t version) override;
  absl::Status DeleteMarkerSet(const std::string& map_id) override;

 private:
  SqlDatabase* db_;
};

/// Zone sets on an SqlDatabase (SQLite or PostgreSQL), each version stored as zone YAML.
/// Thread-safe.
class SqlZoneSetRepository final : public ZoneSetRepository {
 public:
  explicit SqlZoneSetRepository(SqlDatabase* db) : db_(db) {}

  absl::StatusOr<uint32_t> PutZoneSet(const ZoneSet& zones, int64_t created_unix_ms) override;
  absl::StatusOr<StoredZoneSet> GetZoneSet(const std::string& map_id, uint32_t version) override;
  absl::StatusOr<std::vector<StoredZoneSet>> ListZoneSets() override;
  absl::Status DeleteZoneSet(const std::string& map_id) override;

 private:
  SqlDatabase* db_;
};

/// Operators' stops on an SqlDatabase (SQLite or PostgreSQL), one row per scope. Thread-safe.
class SqlStopRepository final : public StopRepository {
 public:
  explicit SqlStopRepository(SqlDatabase* db) : db_(db) {}

  absl::Status PutStop(const RobotStop& stop) override;
  absl::Status DeleteStop(const std::string& map_id, const std::string& zone) override;
  absl::StatusOr<std::vector<RobotStop>> ListStops() override;

 private:
  SqlDatabase* db_;
};

/// Routes on an SqlDatabase (SQLite or PostgreSQL), each version stored as route YAML. Thread-safe.
class SqlRouteRepository final : public RouteRepository {
 public:
  explicit SqlRouteRepository(SqlDatabase* db) : db_(db) {}
  absl::StatusOr<uint32_t> PutRoute(const Route& route, int64_t created_unix_ms) override;
  absl::StatusOr<StoredRoute> GetRoute(const std::string& name, uint32_t version) override;
  absl::StatusOr<std::vector<StoredRoute>> ListRoutes(const std::string& map_id) override;
  absl::StatusOr<int> CountRoutesOnMap(const std::string& map_id) override;
  absl::Status DeleteRoute(const std::string& name) override;

 private:
  SqlDatabase* db_;
};

/// Robots on an SqlDatabase (SQLite or PostgreSQL). Thread-safe.
class SqlRobotRepository final : public RobotRepository {
 public:
  explicit SqlRobotRepository(SqlDatabase* db) : db_(db) {}
  absl::Status UpsertRobot(const StoredRobot& robot) override;
  absl::StatusOr<std::vector<StoredRobot>> ListRobots() override;
  absl::Status DeleteRobot(const std::string& robot_id) override;

 private:
  SqlDatabase* db_;
};

/// Jobs and events on an SqlDatabase (SQLite or PostgreSQL): a job row and its event rows change in
/// one transaction; the idempotency key is a unique index. Thread-safe.
class SqlJobRepository final : public JobRepository {
 public:
  explicit SqlJobRepository(SqlDatabase* db) : db_(db) {}
  absl::StatusOr<CreatedJob> CreateJob(Job job, JobEvent first_event) override;
  absl::StatusOr<Job> GetJob(const std::string& job_id) override;
  absl::StatusOr<JobPage> ListJobs(const JobFilter& filter) override;
  absl::StatusOr<std::map<JobState, int64_t>> CountJobsByState() override;
  absl::StatusOr<int64_t> UpdateJob(const Job& job, JobEvent event) override;
  absl::StatusOr<std::vector<JobEvent>> ListEvents(const std::string& job_id,
                                                   int64_t after_sequence) override;

 private:
  SqlDatabase* db_;
};

/// Operator tokens on an SqlDatabase (SQLite or PostgreSQL): the name is the key and the secret's
/// hash is unique, so neither can be stored twice. Thread-safe.
class SqlOperatorTokenRepository final : public OperatorTokenRepository {
 public:
  explicit SqlOperatorTokenRepository(SqlDatabase* db) : db_(db) {}
  absl::Status InsertToken(const StoredOperatorToken& stored) override;
  absl::StatusOr<std::vector<StoredOperatorToken>> ListTokens() override;
  absl::Status DeleteToken(const std::string& name) override;

 private:
  SqlDatabase* db_;
};

/// Pose history on an SqlDatabase (SQLite or PostgreSQL): one transaction per batch. Thread-safe.
class SqlPoseHistoryRepository final : public PoseHistoryRepository {
 public:
  explicit SqlPoseHistoryRepository(SqlDatabase* db) : db_(db) {}
  absl::Status AppendPoses(const std::vector<PoseSample>& samples) override;
  absl::StatusOr<std::vector<PoseSample>> ListPoses(const std::string& robot_id,
                                                    int64_t since_unix_ms, int limit) override;
  absl::StatusOr<int64_t> PruneBefore(int64_t before_unix_ms) override;

 private:
  SqlDatabase* db_;
};

}  // namespace fleetnav::storage
