#pragma once

#include <string>

#include "fleetnav/planner/movingai.hpp"

namespace fleetnav::planner::testing {

/// Parses an inline map given as rows of MovingAI characters; aborts the test on error.
inline MovingAiMap InlineMap(const std::string& rows_joined_by_newline, int width, int height) {
  std::string text = "type octile\nheight " + std::to_string(height) + "\nwidth " +
                     std::to_string(width) + "\nmap\n" + rows_joined_by_newline;
  return ParseMovingAiMap(text).value();
}

/// Path of a file in the shared MovingAI data folder.
inline std::string MapfDataPath(const std::string& name) {
  return std::string(FLEETNAV_MAPF_DATA_DIR) + "/" + name;
}

}  // namespace fleetnav::planner::testing
