// Scenario files of fleetnav-scenario. A scenario names its world by a path relative to its own
// folder, as the shipped ones do ("../../sim/worlds/barn.yaml"), so the input is written two
// folders below a scratch folder in which `sim` and `deploy` lead to the source tree's.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "fleetnav/scenario/scenario.hpp"

namespace {

std::string ScenarioPath() {
  const std::filesystem::path root =
      std::filesystem::temp_directory_path() / ("fleetnav-fuzz-" + std::to_string(::getpid()));
  std::filesystem::create_directories(root / "tests" / "scenarios");
  std::error_code ignored;
  std::filesystem::create_directory_symlink(FLEETNAV_SOURCE_DIR "/sim", root / "sim", ignored);
  std::filesystem::create_directory_symlink(FLEETNAV_SOURCE_DIR "/deploy", root / "deploy",
                                            ignored);
  return (root / "tests" / "scenarios" / "input.yaml").string();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string kPath = ScenarioPath();
  {
    std::ofstream out(kPath, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  (void)fleetnav::scenario::LoadScenario(kPath);
  return 0;
}
