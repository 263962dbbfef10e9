// fleetnavd addresses as gRPC targets: one address as it is, a replica list as gRPC's
// address list, and lists gRPC cannot take refused naming the entry.
#include "fleetnav/proto/server_target.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace fleetnav {
namespace {

using ::testing::HasSubstr;

TEST(ServerTargetTest, OneAddressOrAnyGrpcTargetStaysAsItIs) {
  EXPECT_EQ(*ServerTarget("127.0.0.1:50051"), "127.0.0.1:50051");
  EXPECT_EQ(*ServerTarget("fleet.example:50051"), "fleet.example:50051");
  EXPECT_EQ(*ServerTarget("dns:///fleet.example:50051"), "dns:///fleet.example:50051");
  EXPECT_EQ(*ServerTarget("ipv4:127.0.0.1:1,127.0.0.1:2"), "ipv4:127.0.0.1:1,127.0.0.1:2");
  EXPECT_EQ(ServerTarget("").status().code(), absl::StatusCode::kInvalidArgument);
}

TEST(ServerTargetTest, AReplicaListBecomesGrpcsAddressList) {
  EXPECT_EQ(*ServerTarget("127.0.0.1:7001,10.0.0.2:7001,localhost:7003"),
            "ipv4:127.0.0.1:7001,10.0.0.2:7001,127.0.0.1:7003");
  EXPECT_EQ(*ServerTarget("[::1]:7001,[fd00::2]:7001"), "ipv6:[::1]:7001,[fd00::2]:7001");
}

TEST(ServerTargetTest, ListsGrpcCannotTakeAreRefusedNamingTheEntry) {
  const absl::StatusOr<std::string> named = ServerTarget("127.0.0.1:7001,fleet-b:7001");
  EXPECT_EQ(named.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(named.status().message(), HasSubstr("'fleet-b:7001' is a host name"));
  const absl::StatusOr<std::string> mixed = ServerTarget("127.0.0.1:7001,[::1]:7001");
  EXPECT_THAT(mixed.status().message(), HasSubstr("mixes IPv4 and IPv6"));
  const absl::StatusOr<std::string> empty = ServerTarget("127.0.0.1:7001,,127.0.0.1:7002");
  EXPECT_THAT(empty.status().message(), HasSubstr("every entry must be IP:port"));
  EXPECT_EQ(ServerTarget("127.0.0.1,127.0.0.2:1").status().code(),
            absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace fleetnav
