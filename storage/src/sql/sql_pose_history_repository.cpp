#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/storage/sql/sql_fleet_repositories.hpp"

namespace fleetnav::storage {

absl::Status SqlPoseHistoryRepository::AppendPoses(const std::vector<PoseSample>& samples) {
  if (samples.empty()) return absl::OkStatus();
  return db_->Transaction([&]() -> absl::Status {
    ASSIGN_OR_RETURN(SqlStatement insert,
                     db_->Prepare("INSERT INTO pose_history (robot_id, unix_ms, stamp_ns, x_m, "
                                  "y_m, yaw_rad) VALUES (?, ?, ?, ?, ?, ?)"));
    for (const PoseSample& sample : samples) {
      insert.Reset();
      insert.Bind(1, sample.robot_id)
          .Bind(2, sample.unix_ms)
          .Bind(3, sample.stamp_ns)
          .Bind(4, sample.pose_in_map.x_m())
          .Bind(5, sample.pose_in_map.y_m())
          .Bind(6, sample.pose_in_map.yaw_rad());
      RETURN_IF_ERROR(insert.Run());
    }
    return absl::OkStatus();
  });
}

absl::StatusOr<std::vector<PoseSample>> SqlPoseHistoryRepository::ListPoses(
    const std::string& robot_id, int64_t since_unix_ms, int limit) {
  std::vector<PoseSample> out;
  RETURN_IF_ERROR(db_->Transaction([&]() -> absl::Status {
    ASSIGN_OR_RETURN(SqlStatement query,
                     db_->Prepare("SELECT unix_ms, stamp_ns, x_m, y_m, yaw_rad FROM pose_history "
                                  "WHERE robot_id = ? AND unix_ms >= ? ORDER BY unix_ms, stamp_ns "
                                  "LIMIT ?"));
    query.Bind(1, robot_id).Bind(2, since_unix_ms).Bind(3, static_cast<int64_t>(limit));
    while (true) {
      ASSIGN_OR_RETURN(bool has_row, query.Step());
      if (!has_row) break;
      out.push_back(
          PoseSample{robot_id, query.ColumnInt(0), query.ColumnInt(1),
                     Pose2(query.ColumnDouble(2), query.ColumnDouble(3), query.ColumnDouble(4))});
    }
    return absl::OkStatus();
  }));
  return out;
}

absl::StatusOr<int64_t> SqlPoseHistoryRepository::PruneBefore(int64_t before_unix_ms) {
  int64_t removed = 0;
  RETURN_IF_ERROR(db_->Transaction([&]() -> absl::Status {
    ASSIGN_OR_RETURN(SqlStatement remove,
                     db_->Prepare("DELETE FROM pose_history WHERE unix_ms < ?"));
    remove.Bind(1, before_unix_ms);
    RETURN_IF_ERROR(remove.Run());
    removed = db_->ChangedRows();
    return absl::OkStatus();
  }));
  return removed;
}

}  // namespace fleetnav::storage
