// fleetnavd's authorization rules without a network: tokens, roles and robot certificates.
#include "fleetnav/server/access/access_policy.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace fleetnav::server {
namespace {

using ::testing::HasSubstr;

constexpr char kFleet[] = "/fleetnav.v1.FleetService/";

AccessPolicy Policy() {
  return *AccessPolicy::Create({{"ada", Role::kAdmin, Sha256Hex("ada-secret")},
                                {"otto", Role::kOperator, Sha256Hex("otto-secret")},
                                {"vic", Role::kViewer, Sha256Hex("vic-secret")}});
}

CallerCredentials Bearer(const std::string& token) { return {"Bearer " + token, ""}; }

TEST(AccessPolicyTest, Sha256IsWhatSha256sumPrints) {
  EXPECT_EQ(Sha256Hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(Sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

TEST(AccessPolicyTest, RolesIncludeTheOnesBelow) {
  const AccessPolicy policy = Policy();
  const std::string put_map = std::string(kFleet) + "PutMap";
  const std::string submit = std::string(kFleet) + "SubmitJob";
  const std::string list = std::string(kFleet) + "ListJobs";
  for (const char* token : {"ada-secret", "otto-secret", "vic-secret"}) {
    EXPECT_TRUE(policy.Authorize(list, Bearer(token)).ok()) << token;
  }
  EXPECT_TRUE(policy.Authorize(submit, Bearer("otto-secret")).ok());
  EXPECT_TRUE(policy.Authorize(submit, Bearer("ada-secret")).ok());
  EXPECT_EQ(policy.Authorize(submit, Bearer("vic-secret")).status().code(),
            absl::StatusCode::kPermissionDenied);
  EXPECT_EQ(policy.Authorize(put_map, Bearer("otto-secret")).status().code(),
            absl::StatusCode::kPermissionDenied);
  const absl::StatusOr<Caller> admin = policy.Authorize(put_map, Bearer("ada-secret"));
  ASSERT_TRUE(admin.ok());
  EXPECT_EQ(admin->name, "ada");
  EXPECT_EQ(admin->role, Role::kAdmin);
  EXPECT_THAT(policy.Authorize(put_map, Bearer("vic-secret")).status().message(),
              HasSubstr("token 'vic' has role viewer, the method needs admin"));
}

TEST(AccessPolicyTest, MissingMalformedAndUnknownTokensAreUnauthenticated) {
  const AccessPolicy policy = Policy();
  const std::string method = std::string(kFleet) + "GetJob";
  for (const CallerCredentials& credentials :
       {CallerCredentials{}, CallerCredentials{"vic-secret", ""}, CallerCredentials{"Bearer", ""},
        CallerCredentials{"Bearer ", ""}, CallerCredentials{"Bearervic-secret", ""},
        CallerCredentials{"Basic vic-secret", ""}, Bearer("vic-secret "), Bearer("nobody")}) {
    const absl::Status status = policy.Authorize(method, credentials).status();
    EXPECT_EQ(status.code(), absl::StatusCode::kUnauthenticated) << credentials.authorization;
    EXPECT_THAT(status.message(), HasSubstr("GetJob"));
  }
}

TEST(AccessPolicyTest, TheBearerSchemeIsCaseInsensitive) {
  // RFC 7235 section 2.1: the authentication scheme is a case-insensitive token.
  const AccessPolicy policy = Policy();
  const std::string method = std::string(kFleet) + "GetJob";
  for (const char* header :
       {"Bearer vic-secret", "bearer vic-secret", "BEARER vic-secret", "bEaReR  vic-secret"}) {
    const absl::StatusOr<Caller> caller = policy.Authorize(method, CallerCredentials{header, ""});
    ASSERT_TRUE(caller.ok()) << header << ": " << caller.status();
    EXPECT_EQ(caller->name, "vic") << header;
  }
}

TEST(AccessPolicyTest, RobotCertificatesOpenTheAgentStreamAndSiteReadsOnly) {
  const AccessPolicy policy = Policy();
  const CallerCredentials robot{"", "lely1"};
  const absl::StatusOr<Caller> stream =
      policy.Authorize("/fleetnav.v1.AgentService/Connect", robot);
  ASSERT_TRUE(stream.ok());
  EXPECT_TRUE(stream->is_robot);
  EXPECT_EQ(stream->name, "lely1");
  EXPECT_TRUE(policy.Authorize(std::string(kFleet) + "GetMap", robot).ok());
  EXPECT_TRUE(policy.Authorize(std::string(kFleet) + "GetMarkerSet", robot).ok());
  EXPECT_EQ(policy.Authorize(std::string(kFleet) + "SubmitJob", robot).status().code(),
            absl::StatusCode::kUnauthenticated);
  EXPECT_EQ(policy.Authorize(std::string(kFleet) + "ListRobots", robot).status().code(),
            absl::StatusCode::kUnauthenticated);
  // A token is no robot.
  EXPECT_EQ(
      policy.Authorize("/fleetnav.v1.AgentService/Connect", Bearer("ada-secret")).status().code(),
      absl::StatusCode::kUnauthenticated);
}

TEST(AccessPolicyTest, UnknownMethodsAreRefusedToEveryoneAndHealthIsOpen) {
  const AccessPolicy policy = Policy();
  EXPECT_EQ(policy.Authorize("/fleetnav.v1.FleetService/DropTables", Bearer("ada-secret"))
                .status()
                .code(),
            absl::StatusCode::kPermissionDenied);
  EXPECT_EQ(
      policy.Authorize("/fleetnav.v1.FleetServiceX/GetJob", Bearer("ada-secret")).status().code(),
      absl::StatusCode::kPermissionDenied);
  EXPECT_EQ(policy.Authorize("", Bearer("ada-secret")).status().code(),
            absl::StatusCode::kPermissionDenied);
  EXPECT_TRUE(policy.Authorize("/grpc.health.v1.Health/Check", {}).ok());
}

TEST(AccessPolicyTest, BadTokenTablesAreRefused) {
  EXPECT_EQ(AccessPolicy::Create({{"a", Role::kAdmin, "abc"}}).status().code(),
            absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(AccessPolicy::Create({{"a", Role::kAdmin, std::string(64, 'A')}}).status().code(),
            absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(AccessPolicy::Create(
                  {{"a", Role::kAdmin, Sha256Hex("x")}, {"a", Role::kViewer, Sha256Hex("y")}})
                  .status()
                  .message(),
              HasSubstr("given twice"));
  EXPECT_THAT(AccessPolicy::Create(
                  {{"a", Role::kAdmin, Sha256Hex("x")}, {"b", Role::kViewer, Sha256Hex("x")}})
                  .status()
                  .message(),
              HasSubstr("share one hash"));
}

}  // namespace
}  // namespace fleetnav::server
