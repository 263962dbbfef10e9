#include "fleetnav/server/robots/pose_history_recorder.hpp"

#include <cmath>
#include <vector>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/status_macros.hpp"

namespace fleetnav::server {

absl::Status PoseHistoryParams::Validate() const {
  if (!(period_s > 0.0 && std::isfinite(period_s))) {
    return absl::InvalidArgumentError(absl::StrCat("period_s: must be > 0, got ", period_s));
  }
  if (!(retention_s > 0.0 && std::isfinite(retention_s))) {
    return absl::InvalidArgumentError(absl::StrCat("retention_s: must be > 0, got ", retention_s));
  }
  return absl::OkStatus();
}

absl::StatusOr<int> PoseHistoryRecorder::RecordOnce(int64_t now_unix_ms) {
  std::vector<storage::PoseSample> samples;
  for (const RobotRecord& record : registry_->Snapshot()) {
    if (!record.last_telemetry) continue;
    uint64_t& seen = recorded_count_[record.identity.robot_id];
    if (record.telemetry_count == seen) continue;  // nothing new from this robot
    seen = record.telemetry_count;
    samples.push_back({record.identity.robot_id, now_unix_ms, record.last_telemetry->stamp_ns,
                       record.last_telemetry->pose_in_map});
  }
  RETURN_IF_ERROR(history_->AppendPoses(samples));
  if (now_unix_ms - last_prune_unix_ms_ >= 60'000) {
    last_prune_unix_ms_ = now_unix_ms;
    RETURN_IF_ERROR(
        history_->PruneBefore(now_unix_ms - static_cast<int64_t>(params_.retention_s * 1000))
            .status());
  }
  return static_cast<int>(samples.size());
}

}  // namespace fleetnav::server
