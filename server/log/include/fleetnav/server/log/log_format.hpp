#pragma once

#include <spdlog/formatter.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "absl/status/statusor.h"
#include "fleetnav/core/job.hpp"

namespace fleetnav::server::log {

/// How fleetnavd writes its log lines (`--log-format`).
enum class LogFormat { kText, kJson };

/// "text" or "json"; InvalidArgument naming the text otherwise.
absl::StatusOr<LogFormat> ParseLogFormat(const std::string& text);

/// A log line's message with named fields (job and robot ids, states).
struct LogFields {
  std::string message;
  std::vector<std::pair<std::string, std::string>> fields;
};

/// The payload to hand spdlog for `line` in `format`: text "message key=value ...", or for
/// JSON the message, a tab and the fields as one JSON object, which JsonLogFormatter unpacks.
std::string FormatLogPayload(LogFormat format, const LogFields& line);

/// spdlog formatter writing one JSON object per line: {"ts": ISO 8601 UTC with milliseconds,
/// "level", "msg", and the fields FormatLogPayload packed}. Every message is escaped, so any
/// line of any part of fleetnavd stays valid JSON.
class JsonLogFormatter final : public spdlog::formatter {
 public:
  void format(const spdlog::details::log_msg& msg, spdlog::memory_buf_t& dest) override;
  std::unique_ptr<spdlog::formatter> clone() const override;
};

/// The log line of a job event that changes the job's state (queued, assigned, started,
/// paused, resumed, succeeded, failed, cancelled); nullopt for progress and other events.
std::optional<LogFields> JobTransitionLine(const Job& job, const JobEvent& event);

}  // namespace fleetnav::server::log
