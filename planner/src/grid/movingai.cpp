#include "fleetnav/planner/grid/movingai.hpp"

#include <charconv>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "absl/strings/str_cat.h"

namespace fleetnav::planner {
namespace {

absl::Status LineError(int line, const std::string& what) {
  return absl::InvalidArgumentError(absl::StrCat("line ", line, ": ", what));
}

// Splits on `sep`; with skip_empty, empty pieces are dropped.
std::vector<std::string_view> Split(std::string_view text, char sep, bool skip_empty = false) {
  std::vector<std::string_view> parts;
  size_t begin = 0;
  while (true) {
    const size_t end = text.find(sep, begin);
    const std::string_view piece =
        text.substr(begin, end == std::string_view::npos ? std::string_view::npos : end - begin);
    if (!skip_empty || !piece.empty()) parts.push_back(piece);
    if (end == std::string_view::npos) break;
    begin = end + 1;
  }
  return parts;
}

bool ParseInt(std::string_view text, int* value) {
  const char* end = text.data() + text.size();
  auto [ptr, ec] = std::from_chars(text.data(), end, *value);
  return ec == std::errc() && ptr == end && !text.empty();
}

bool ParseDouble(std::string_view text, double* value) {
  const std::string copy(text);
  char* end = nullptr;
  *value = std::strtod(copy.c_str(), &end);
  return !copy.empty() && end == copy.c_str() + copy.size();
}

bool StartsWith(std::string_view text, std::string_view prefix) {
  return text.substr(0, prefix.size()) == prefix;
}

std::string_view StripTrailingSpace(std::string_view text) {
  while (!text.empty() && (text.back() == ' ' || text.back() == '\t')) text.remove_suffix(1);
  return text;
}

std::vector<std::string_view> SplitLines(std::string_view text) {
  std::vector<std::string_view> lines = Split(text, '\n');
  for (auto& line : lines) {
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  }
  // A trailing newline does not start an extra line.
  while (!lines.empty() && lines.back().empty()) lines.pop_back();
  return lines;
}

// Parses "<key> <integer>" into value.
absl::Status ParseHeaderInt(std::string_view line, std::string_view key, int line_number,
                            int* value) {
  std::vector<std::string_view> parts = Split(line, ' ', true);
  if (parts.size() != 2 || parts[0] != key) {
    return LineError(line_number, absl::StrCat("expected '", std::string(key), " <n>'"));
  }
  if (!ParseInt(parts[1], value) || *value <= 0 || *value > 100000) {
    return LineError(line_number,
                     absl::StrCat("bad ", std::string(key), " '", std::string(parts[1]), "'"));
  }
  return absl::OkStatus();
}

absl::StatusOr<std::string> ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return absl::NotFoundError(absl::StrCat("cannot open ", path));
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

absl::Status WithPath(const absl::Status& status, const std::string& path) {
  return absl::Status(status.code(), absl::StrCat(path, ": ", status.message()));
}

}  // namespace

absl::StatusOr<MovingAiMap> ParseMovingAiMap(std::string_view text) {
  const std::vector<std::string_view> lines = SplitLines(text);
  if (lines.size() < 4) return LineError(static_cast<int>(lines.size()) + 1, "truncated header");
  if (!StartsWith(lines[0], "type ")) return LineError(1, "expected 'type <name>'");
  MovingAiMap map;
  if (absl::Status s = ParseHeaderInt(lines[1], "height", 2, &map.height); !s.ok()) return s;
  if (absl::Status s = ParseHeaderInt(lines[2], "width", 3, &map.width); !s.ok()) return s;
  if (StripTrailingSpace(lines[3]) != "map") return LineError(4, "expected 'map'");
  if (static_cast<int64_t>(map.width) * map.height > 100'000'000) {
    return LineError(3, "map too large");
  }
  if (static_cast<int>(lines.size()) - 4 < map.height) {
    return LineError(static_cast<int>(lines.size()) + 1,
                     absl::StrCat("expected ", map.height, " rows, got ", lines.size() - 4));
  }
  if (static_cast<int>(lines.size()) - 4 > map.height) {
    return LineError(4 + map.height + 1, "extra rows after the map");
  }
  map.passable.assign(static_cast<size_t>(map.width) * map.height, false);
  for (int y = 0; y < map.height; ++y) {
    const std::string_view row = lines[4 + y];
    const int line_number = 5 + y;
    if (static_cast<int>(row.size()) != map.width) {
      return LineError(line_number,
                       absl::StrCat("row has ", row.size(), " cells, expected ", map.width));
    }
    for (int x = 0; x < map.width; ++x) {
      switch (row[x]) {
        case '.':
        case 'G':
        case 'S':
          map.passable[static_cast<size_t>(y) * map.width + x] = true;
          break;
        case '@':
        case 'O':
        case 'T':
        case 'W':
          break;
        default:
          return LineError(line_number, absl::StrCat("unknown cell character '",
                                                     std::string(1, row[x]), "' at x=", x));
      }
    }
  }
  return map;
}

absl::StatusOr<MovingAiMap> LoadMovingAiMap(const std::string& path) {
  absl::StatusOr<std::string> text = ReadFile(path);
  if (!text.ok()) return text.status();
  absl::StatusOr<MovingAiMap> map = ParseMovingAiMap(*text);
  if (!map.ok()) return WithPath(map.status(), path);
  return map;
}

absl::StatusOr<std::vector<ScenarioEntry>> ParseMovingAiScenario(std::string_view text) {
  const std::vector<std::string_view> lines = SplitLines(text);
  if (lines.empty() || !StartsWith(lines[0], "version")) {
    return LineError(1, "expected 'version <n>'");
  }
  std::vector<ScenarioEntry> entries;
  for (size_t i = 1; i < lines.size(); ++i) {
    const int line_number = static_cast<int>(i) + 1;
    if (lines[i].empty()) continue;
    std::vector<std::string_view> f = Split(lines[i], '\t');
    if (f.size() != 9) {
      return LineError(line_number,
                       absl::StrCat("expected 9 tab-separated fields, got ", f.size()));
    }
    ScenarioEntry e;
    e.map_name = std::string(f[1]);
    int* ints[] = {&e.bucket,  nullptr,    &e.map_width, &e.map_height,
                   &e.start_x, &e.start_y, &e.goal_x,    &e.goal_y};
    static constexpr const char* kNames[] = {"bucket",  "map",     "width",  "height",
                                             "start_x", "start_y", "goal_x", "goal_y"};
    for (int k = 0; k < 8; ++k) {
      if (ints[k] == nullptr) continue;
      if (!ParseInt(f[k], ints[k]) || *ints[k] < 0) {
        return LineError(line_number,
                         absl::StrCat("bad ", kNames[k], " '", std::string(f[k]), "'"));
      }
    }
    if (!ParseDouble(f[8], &e.optimal_length) || e.optimal_length < 0) {
      return LineError(line_number, absl::StrCat("bad optimal length '", std::string(f[8]), "'"));
    }
    if (e.start_x >= e.map_width || e.goal_x >= e.map_width || e.start_y >= e.map_height ||
        e.goal_y >= e.map_height) {
      return LineError(line_number, "start or goal outside the map size");
    }
    entries.push_back(std::move(e));
  }
  return entries;
}

absl::StatusOr<std::vector<ScenarioEntry>> LoadMovingAiScenario(const std::string& path) {
  absl::StatusOr<std::string> text = ReadFile(path);
  if (!text.ok()) return text.status();
  absl::StatusOr<std::vector<ScenarioEntry>> entries = ParseMovingAiScenario(*text);
  if (!entries.ok()) return WithPath(entries.status(), path);
  return entries;
}

}  // namespace fleetnav::planner
