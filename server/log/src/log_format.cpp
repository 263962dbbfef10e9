#include "fleetnav/server/log/log_format.hpp"

#include <spdlog/details/log_msg.h>

#include <chrono>
#include <ctime>
#include <nlohmann/json.hpp>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"

namespace fleetnav::server::log {

absl::StatusOr<LogFormat> ParseLogFormat(const std::string& text) {
  if (text == "text") return LogFormat::kText;
  if (text == "json") return LogFormat::kJson;
  return absl::InvalidArgumentError(
      absl::StrCat("log format '", text, "' is neither text nor json"));
}

std::string FormatLogPayload(LogFormat format, const LogFields& line) {
  if (format == LogFormat::kText) {
    std::string text = line.message;
    for (const auto& [key, value] : line.fields) absl::StrAppend(&text, " ", key, "=", value);
    return text;
  }
  nlohmann::json fields = nlohmann::json::object();
  for (const auto& [key, value] : line.fields) fields[key] = value;
  return absl::StrCat(line.message, "\t", fields.dump());
}

void JsonLogFormatter::format(const spdlog::details::log_msg& msg, spdlog::memory_buf_t& dest) {
  const std::string payload(msg.payload.data(), msg.payload.size());
  nlohmann::json line = nlohmann::json::object();
  const auto since_epoch = msg.time.time_since_epoch();
  const std::time_t seconds = std::chrono::duration_cast<std::chrono::seconds>(since_epoch).count();
  const int millis = static_cast<int>(
      std::chrono::duration_cast<std::chrono::milliseconds>(since_epoch).count() % 1000);
  std::tm utc{};
  gmtime_r(&seconds, &utc);
  line["ts"] =
      absl::StrFormat("%04d-%02d-%02dT%02d:%02d:%02d.%03dZ", utc.tm_year + 1900, utc.tm_mon + 1,
                      utc.tm_mday, utc.tm_hour, utc.tm_min, utc.tm_sec, millis);
  line["level"] = std::string(spdlog::level::to_string_view(msg.level).data(),
                              spdlog::level::to_string_view(msg.level).size());
  // A payload packed by FormatLogPayload: the message, a tab, the fields as a JSON object.
  const size_t tab = payload.rfind("\t{");
  nlohmann::json fields;
  if (tab != std::string::npos) {
    fields = nlohmann::json::parse(payload.substr(tab + 1), nullptr, /*allow_exceptions=*/false);
  }
  if (fields.is_object()) {
    line["msg"] = payload.substr(0, tab);
    for (auto& [key, value] : fields.items()) line[key] = value;
  } else {
    line["msg"] = payload;
  }
  const std::string text =
      line.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
  dest.append(text.data(), text.data() + text.size());
}

std::unique_ptr<spdlog::formatter> JsonLogFormatter::clone() const {
  return std::make_unique<JsonLogFormatter>();
}

std::optional<LogFields> JobTransitionLine(const Job& job, const JobEvent& event) {
  switch (event.type) {
    case JobEventType::kQueued:
    case JobEventType::kAssigned:
    case JobEventType::kStarted:
    case JobEventType::kPaused:
    case JobEventType::kResumed:
    case JobEventType::kSucceeded:
    case JobEventType::kFailed:
    case JobEventType::kCancelled:
      break;
    default:
      return std::nullopt;
  }
  LogFields line;
  const std::string state(JobStateName(event.state));
  const std::string robot = !event.robot_id.empty() ? event.robot_id : job.assigned_robot_id;
  line.message = absl::StrCat("job ", job.job_id, " ", state,
                              robot.empty() ? "" : absl::StrCat(" (robot ", robot, ")"),
                              event.reason.empty() ? "" : absl::StrCat(": ", event.reason));
  line.fields = {
      {"event", "job_transition"}, {"job_id", job.job_id}, {"state", state}, {"robot_id", robot}};
  if (!job.route_name.empty()) line.fields.emplace_back("route", job.route_name);
  if (!event.reason.empty()) line.fields.emplace_back("reason", event.reason);
  return line;
}

}  // namespace fleetnav::server::log
