// The replicas' relay key and pinned certificate (replica_relay.hpp), on a development PKI.
#include "fleetnav/server/rpc/replica_relay.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "absl/strings/str_cat.h"

namespace fleetnav::server {
namespace {

using ::testing::HasSubstr;
using ::testing::MatchesRegex;

std::string Read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

class ReplicaRelayTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir = new std::string(
        (std::filesystem::path(::testing::TempDir()) / absl::StrCat("relay-pki-", getpid()))
            .string());
    const std::string command =
        absl::StrCat(FLEETNAV_DEPLOY_DIR, "/certs/make-dev-certs ", *dir, " lely1 >/dev/null");
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
  }
  static void TearDownTestSuite() {
    std::filesystem::remove_all(*dir);
    delete dir;
  }
  static std::string Pki(const std::string& name) { return Read(*dir + "/" + name); }
  static std::string* dir;
};

std::string* ReplicaRelayTest::dir = nullptr;

TEST_F(ReplicaRelayTest, TheKeyComesFromTheServerKeyAlone) {
  const absl::StatusOr<std::string> key = ReplicaRelayKey(Pki("server.key"));
  ASSERT_TRUE(key.ok()) << key.status();
  EXPECT_THAT(*key, MatchesRegex("[0-9a-f]{64}"));
  // Every replica with the same key file makes the same relay key; another key another one.
  EXPECT_EQ(*ReplicaRelayKey(Pki("server.key")), *key);
  const absl::StatusOr<std::string> other = ReplicaRelayKey(Pki("robot-lely1.key"));
  ASSERT_TRUE(other.ok());
  EXPECT_NE(*other, *key);
  // A certificate, or nothing, is no key.
  EXPECT_EQ(ReplicaRelayKey(Pki("server.crt")).status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(ReplicaRelayKey("").status().code(), absl::StatusCode::kInvalidArgument);
}

TEST_F(ReplicaRelayTest, OnlyTheExactKeyMatches) {
  const std::string key = *ReplicaRelayKey(Pki("server.key"));
  EXPECT_TRUE(IsReplicaRelayKey(key, key));
  std::string altered = key;
  altered.back() = altered.back() == '0' ? '1' : '0';
  EXPECT_FALSE(IsReplicaRelayKey(altered, key));
  EXPECT_FALSE(IsReplicaRelayKey(key.substr(1), key));
  EXPECT_FALSE(IsReplicaRelayKey("", key));
  // A server that takes no relayed calls has no key: nothing matches it, not even nothing.
  EXPECT_FALSE(IsReplicaRelayKey("", ""));
}

TEST_F(ReplicaRelayTest, ThePinnedCertificateIsTheFirstOfTheChain) {
  const std::string leaf = Pki("server.crt");
  const absl::StatusOr<std::string> pinned = LeafCertificatePem(leaf + Pki("server-ca.crt"));
  ASSERT_TRUE(pinned.ok()) << pinned.status();
  EXPECT_EQ(*pinned, *LeafCertificatePem(leaf));
  EXPECT_NE(*pinned, *LeafCertificatePem(Pki("server-ca.crt")));
  EXPECT_THAT(*pinned, HasSubstr("-----BEGIN CERTIFICATE-----"));
  EXPECT_EQ(LeafCertificatePem(Pki("server.key")).status().code(),
            absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace fleetnav::server
