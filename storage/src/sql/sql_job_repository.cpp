#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "fleetnav/core/echo_input.hpp"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/storage/sql/sql_fleet_repositories.hpp"

namespace fleetnav::storage {
namespace {

constexpr char kJobColumns[] =
    "job_id, state, route_name, route_version, map_id, has_goal, goal_x_m, goal_y_m, "
    "goal_yaw_rad, requested_robot_id, assigned_robot_id, priority, idempotency_key, "
    "on_robot_lost, created_unix_ms, updated_unix_ms, progress_fraction, reason, seq";

Job JobFromRow(const SqlStatement& row) {
  Job job;
  job.job_id = row.ColumnText(0);
  job.state = static_cast<JobState>(row.ColumnInt(1));
  job.route_name = row.ColumnText(2);
  job.route_version = static_cast<uint32_t>(row.ColumnInt(3));
  job.map_id = row.ColumnText(4);
  if (row.ColumnInt(5) != 0) {
    job.goal = Pose2(row.ColumnDouble(6), row.ColumnDouble(7), row.ColumnDouble(8));
  }
  job.requested_robot_id = row.ColumnText(9);
  job.assigned_robot_id = row.ColumnText(10);
  job.priority = static_cast<int>(row.ColumnInt(11));
  job.idempotency_key = row.ColumnIsNull(12) ? "" : row.ColumnText(12);
  job.on_robot_lost = static_cast<RequeuePolicy>(row.ColumnInt(13));
  job.created_unix_ms = row.ColumnInt(14);
  job.updated_unix_ms = row.ColumnInt(15);
  job.progress_fraction = row.ColumnDouble(16);
  job.reason = row.ColumnText(17);
  return job;
}

// Binds the job's columns 2..18 (state .. reason) in the order of kJobColumns.
void BindJobFields(SqlStatement& statement, const Job& job, int first) {
  const Pose2 goal = job.goal.value_or(Pose2());
  statement.Bind(first, static_cast<int64_t>(job.state))
      .Bind(first + 1, job.route_name)
      .Bind(first + 2, static_cast<int64_t>(job.route_version))
      .Bind(first + 3, job.map_id)
      .Bind(first + 4, static_cast<int64_t>(job.goal.has_value()))
      .Bind(first + 5, goal.x_m())
      .Bind(first + 6, goal.y_m())
      .Bind(first + 7, goal.yaw_rad())
      .Bind(first + 8, job.requested_robot_id)
      .Bind(first + 9, job.assigned_robot_id)
      .Bind(first + 10, static_cast<int64_t>(job.priority));
  if (job.idempotency_key.empty()) {
    statement.BindNull(first + 11);
  } else {
    statement.Bind(first + 11, job.idempotency_key);
  }
  statement.Bind(first + 12, static_cast<int64_t>(job.on_robot_lost))
      .Bind(first + 13, job.created_unix_ms)
      .Bind(first + 14, job.updated_unix_ms)
      .Bind(first + 15, job.progress_fraction)
      .Bind(first + 16, job.reason);
}

absl::StatusOr<int64_t> AppendEvent(SqlDatabase* db, JobEvent event) {
  RETURN_IF_ERROR(db->LockKey(absl::StrCat("job_events:", event.job_id)));
  ASSIGN_OR_RETURN(SqlStatement next,
                   db->Prepare("SELECT COALESCE(MAX(sequence), 0) + 1 FROM job_events WHERE "
                               "job_id = ?"));
  next.Bind(1, event.job_id);
  ASSIGN_OR_RETURN(bool has_row, next.Step());
  event.sequence = has_row ? next.ColumnInt(0) : 1;
  ASSIGN_OR_RETURN(SqlStatement insert,
                   db->Prepare("INSERT INTO job_events (job_id, sequence, type, unix_ms, "
                               "robot_id, action_index, progress_fraction, mode, reason, state) "
                               "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?)"));
  insert.Bind(1, event.job_id)
      .Bind(2, event.sequence)
      .Bind(3, static_cast<int64_t>(event.type))
      .Bind(4, event.unix_ms)
      .Bind(5, event.robot_id)
      .Bind(6, static_cast<int64_t>(event.action_index))
      .Bind(7, event.progress_fraction)
      .Bind(8, static_cast<int64_t>(event.mode))
      .Bind(9, event.reason)
      .Bind(10, static_cast<int64_t>(event.state));
  RETURN_IF_ERROR(insert.Run());
  return event.sequence;
}

}  // namespace

absl::StatusOr<CreatedJob> SqlJobRepository::CreateJob(Job job, JobEvent first_event) {
  CreatedJob created;
  RETURN_IF_ERROR(db_->Transaction([&]() -> absl::Status {
    if (!job.idempotency_key.empty()) {
      ASSIGN_OR_RETURN(SqlStatement existing,
                       db_->Prepare(absl::StrCat("SELECT ", kJobColumns,
                                                 " FROM jobs WHERE idempotency_key = ?")));
      existing.Bind(1, job.idempotency_key);
      ASSIGN_OR_RETURN(bool found, existing.Step());
      if (found) {
        created = CreatedJob{JobFromRow(existing), true};
        return absl::OkStatus();
      }
    }
    ASSIGN_OR_RETURN(const int64_t seq, db_->NextNumber("job_numbers", "jobs", "seq"));
    job.job_id = absl::StrFormat("job-%06d", seq);
    ASSIGN_OR_RETURN(SqlStatement insert,
                     db_->Prepare("INSERT INTO jobs (seq, job_id, state, route_name, "
                                  "route_version, map_id, has_goal, goal_x_m, goal_y_m, "
                                  "goal_yaw_rad, requested_robot_id, assigned_robot_id, priority, "
                                  "idempotency_key, on_robot_lost, created_unix_ms, "
                                  "updated_unix_ms, progress_fraction, reason) VALUES "
                                  "(?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)"));
    insert.Bind(1, seq).Bind(2, job.job_id);
    BindJobFields(insert, job, 3);
    RETURN_IF_ERROR(insert.Run());
    first_event.job_id = job.job_id;
    RETURN_IF_ERROR(AppendEvent(db_, first_event).status());
    created = CreatedJob{job, false};
    return absl::OkStatus();
  }));
  return created;
}

absl::StatusOr<Job> SqlJobRepository::GetJob(const std::string& job_id) {
  std::optional<Job> found;
  RETURN_IF_ERROR(db_->Transaction([&]() -> absl::Status {
    ASSIGN_OR_RETURN(SqlStatement query, db_->Prepare(absl::StrCat("SELECT ", kJobColumns,
                                                                   " FROM jobs WHERE job_id = ?")));
    query.Bind(1, job_id);
    ASSIGN_OR_RETURN(bool has_row, query.Step());
    if (has_row) found = JobFromRow(query);
    return absl::OkStatus();
  }));
  if (!found) return absl::NotFoundError(absl::StrCat("job '", EchoInput(job_id), "' not found"));
  return *std::move(found);
}

absl::StatusOr<std::map<JobState, int64_t>> SqlJobRepository::CountJobsByState() {
  std::map<JobState, int64_t> counts;
  RETURN_IF_ERROR(db_->Transaction([&]() -> absl::Status {
    ASSIGN_OR_RETURN(SqlStatement query,
                     db_->Prepare("SELECT state, COUNT(*) FROM jobs GROUP BY state"));
    while (true) {
      ASSIGN_OR_RETURN(bool has_row, query.Step());
      if (!has_row) break;
      counts[static_cast<JobState>(query.ColumnInt(0))] = query.ColumnInt(1);
    }
    return absl::OkStatus();
  }));
  return counts;
}

absl::StatusOr<JobPage> SqlJobRepository::ListJobs(const JobFilter& filter) {
  int64_t after_seq = 0;
  if (!filter.page_token.empty()) {
    char* end = nullptr;
    after_seq = std::strtoll(filter.page_token.c_str(), &end, 10);
    if (end == filter.page_token.c_str() || *end != '\0' || after_seq < 0) {
      return absl::InvalidArgumentError(absl::StrCat(
          "page_token: not a token this server issued: '", EchoInput(filter.page_token), "'"));
    }
  }
  std::string where = "seq > ?";
  if (!filter.states.empty()) {
    where += " AND state IN (";
    for (size_t i = 0; i < filter.states.size(); ++i) {
      absl::StrAppend(&where, i == 0 ? "" : ",", static_cast<int>(filter.states[i]));
    }
    where += ")";
  }
  if (!filter.robot_id.empty()) where += " AND (requested_robot_id = ? OR assigned_robot_id = ?)";
  if (!filter.map_id.empty()) where += " AND map_id = ?";
  JobPage page;
  RETURN_IF_ERROR(db_->Transaction([&]() -> absl::Status {
    ASSIGN_OR_RETURN(SqlStatement query,
                     db_->Prepare(absl::StrCat("SELECT ", kJobColumns, " FROM jobs WHERE ", where,
                                               " ORDER BY seq LIMIT ?")));
    int index = 1;
    query.Bind(index++, after_seq);
    if (!filter.robot_id.empty()) {
      query.Bind(index++, filter.robot_id);
      query.Bind(index++, filter.robot_id);
    }
    if (!filter.map_id.empty()) query.Bind(index++, filter.map_id);
    query.Bind(index++, static_cast<int64_t>(filter.page_size + 1));
    int64_t last_seq = after_seq;
    while (true) {
      ASSIGN_OR_RETURN(bool has_row, query.Step());
      if (!has_row) break;
      if (static_cast<int>(page.jobs.size()) == filter.page_size) {
        page.next_page_token = absl::StrCat(last_seq);
        break;
      }
      page.jobs.push_back(JobFromRow(query));
      last_seq = query.ColumnInt(18);
    }
    return absl::OkStatus();
  }));
  return page;
}

absl::StatusOr<int64_t> SqlJobRepository::UpdateJob(const Job& job, JobEvent event) {
  int64_t sequence = 0;
  RETURN_IF_ERROR(db_->Transaction([&]() -> absl::Status {
    ASSIGN_OR_RETURN(SqlStatement update,
                     db_->Prepare("UPDATE jobs SET state = ?, route_name = ?, route_version = ?, "
                                  "map_id = ?, has_goal = ?, goal_x_m = ?, goal_y_m = ?, "
                                  "goal_yaw_rad = ?, requested_robot_id = ?, "
                                  "assigned_robot_id = ?, priority = ?, idempotency_key = ?, "
                                  "on_robot_lost = ?, created_unix_ms = ?, updated_unix_ms = ?, "
                                  "progress_fraction = ?, reason = ? WHERE job_id = ?"));
    BindJobFields(update, job, 1);
    update.Bind(18, job.job_id);
    RETURN_IF_ERROR(update.Run());
    if (db_->ChangedRows() == 0) {
      return absl::NotFoundError(absl::StrCat("job '", job.job_id, "' not found"));
    }
    event.job_id = job.job_id;
    ASSIGN_OR_RETURN(sequence, AppendEvent(db_, event));
    return absl::OkStatus();
  }));
  return sequence;
}

absl::StatusOr<std::vector<JobEvent>> SqlJobRepository::ListEvents(const std::string& job_id,
                                                                   int64_t after_sequence) {
  std::vector<JobEvent> out;
  RETURN_IF_ERROR(db_->Transaction([&]() -> absl::Status {
    ASSIGN_OR_RETURN(SqlStatement query,
                     db_->Prepare("SELECT sequence, type, unix_ms, robot_id, action_index, "
                                  "progress_fraction, mode, reason, state FROM job_events WHERE "
                                  "job_id = ? AND sequence > ? ORDER BY sequence"));
    query.Bind(1, job_id).Bind(2, after_sequence);
    while (true) {
      ASSIGN_OR_RETURN(bool has_row, query.Step());
      if (!has_row) break;
      JobEvent event;
      event.job_id = job_id;
      event.sequence = query.ColumnInt(0);
      event.type = static_cast<JobEventType>(query.ColumnInt(1));
      event.unix_ms = query.ColumnInt(2);
      event.robot_id = query.ColumnText(3);
      event.action_index = static_cast<int>(query.ColumnInt(4));
      event.progress_fraction = query.ColumnDouble(5);
      event.mode = static_cast<NavigationMode>(query.ColumnInt(6));
      event.reason = query.ColumnText(7);
      event.state = static_cast<JobState>(query.ColumnInt(8));
      out.push_back(std::move(event));
    }
    return absl::OkStatus();
  }));
  return out;
}

}  // namespace fleetnav::storage
