// Every server binary owns its port: a second fleetnavd or fleetnav-sim started on a port that
// one already serves exits non-zero naming the address (gRPC's default SO_REUSEPORT would let it
// start, and the kernel would split the clients between two databases or two worlds).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "fleetnav/scenario/child_process.hpp"

namespace fleetnav {
namespace {

using scenario::ChildProcess;
using ::testing::HasSubstr;

std::string TempPath(const std::string& name) {
  return (std::filesystem::path(::testing::TempDir()) /
          ("ports-" + std::to_string(getpid()) + "-" + name))
      .string();
}

/// Starts `first` on an ephemeral port, then `second` with that port appended, and expects the
/// second to fail naming the address while the first keeps serving.
void ExpectSecondOnThePortRefused(std::vector<std::string> first, std::vector<std::string> second,
                                  const std::string& name) {
  const std::string port_file = TempPath(name + ".port");
  std::filesystem::remove(port_file);
  first.insert(first.end(), {"--listen", "127.0.0.1:0", "--port-file", port_file});
  ChildProcess one(first, TempPath(name + "-1.out"), TempPath(name + "-1.err"));
  const int port = scenario::WaitForPortFile(port_file);
  ASSERT_GT(port, 0) << one.Stderr();
  const std::string address = "127.0.0.1:" + std::to_string(port);
  second.insert(second.end(), {"--listen", address});
  ChildProcess two(second, TempPath(name + "-2.out"), TempPath(name + "-2.err"));
  const std::optional<int> code = two.Wait(30.0);
  ASSERT_TRUE(code.has_value()) << "the second " << name << " is serving " << address;
  EXPECT_NE(*code, 0);
  EXPECT_THAT(two.Stderr() + two.Stdout(), HasSubstr("address " + address + " already in use"));
  EXPECT_TRUE(one.running());
  one.Stop();
}

TEST(ExclusivePortsTest, SecondFleetnavdOnABoundPortExits) {
  ExpectSecondOnThePortRefused({FLEETNAV_FLEETNAVD_PATH, "--insecure", "--db", TempPath("a.db")},
                               {FLEETNAV_FLEETNAVD_PATH, "--insecure", "--db", TempPath("b.db")},
                               "fleetnavd");
}

TEST(ExclusivePortsTest, SecondSimulatorOnABoundPortExits) {
  const std::string world = std::string(FLEETNAV_WORLDS_DIR) + "/barn.yaml";
  ExpectSecondOnThePortRefused({FLEETNAV_SIM_PATH, "--world", world},
                               {FLEETNAV_SIM_PATH, "--world", world}, "fleetnav-sim");
}

}  // namespace
}  // namespace fleetnav
