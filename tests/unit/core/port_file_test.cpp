// WritePortFile: the number appears whole, replaces what an earlier run left, and an unwritable
// place is an error naming the file.
#include "fleetnav/core/port_file.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace fleetnav {
namespace {

TEST(PortFileTest, ReplacesAStaleFileWhole) {
  const std::string path =
      (std::filesystem::path(::testing::TempDir()) / ("port-" + std::to_string(getpid()))).string();
  std::ofstream(path) << "45678\n";  // an earlier run's
  ASSERT_TRUE(WritePortFile(path, 5061).ok());
  std::ifstream in(path);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text, "5061\n");
  EXPECT_FALSE(std::filesystem::exists(path + ".partial"));
  std::filesystem::remove(path);
}

TEST(PortFileTest, AnUnwritablePlaceNamesTheFile) {
  const absl::Status status = WritePortFile("/nonexistent-dir/x.port", 1);
  EXPECT_FALSE(status.ok());
  EXPECT_THAT(status.message(), ::testing::HasSubstr("/nonexistent-dir/x.port"));
}

}  // namespace
}  // namespace fleetnav
