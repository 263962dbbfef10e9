// The operator token file fleetnavd reads (server_security): what a bad file is told.
#include "fleetnav/server/rpc/server_security.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "fleetnav/server/access/access_policy.hpp"

namespace fleetnav::server {
namespace {

using ::testing::HasSubstr;

TEST(OperatorTokensTest, TheFileNamesWhatIsWrong) {
  const std::string hash = Sha256Hex("t");
  const absl::StatusOr<std::vector<OperatorToken>> tokens =
      ParseOperatorTokens("tokens:\n  - {name: ada, role: admin, sha256: " + hash + "}\n");
  ASSERT_TRUE(tokens.ok()) << tokens.status();
  ASSERT_EQ(tokens->size(), 1u);
  EXPECT_EQ((*tokens)[0].role, Role::kAdmin);
  EXPECT_THAT(ParseOperatorTokens("tokens:\n  - {name: a, role: root, sha256: " + hash + "}\n")
                  .status()
                  .message(),
              HasSubstr("tokens[0]: role 'root'"));
  EXPECT_THAT(ParseOperatorTokens("tokens:\n  - {name: a, role: admin}\n").status().message(),
              HasSubstr("needs name, role and sha256"));
  EXPECT_THAT(
      ParseOperatorTokens("tokens:\n  - {name: a, role: admin, token: x, sha256: " + hash + "}\n")
          .status()
          .message(),
      HasSubstr("unknown key 'token'"));
  EXPECT_EQ(ParseOperatorTokens("users: []").status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(ParseOperatorTokens("tokens: [").status().code(), absl::StatusCode::kInvalidArgument);
  // Without an admin nobody could make or revoke tokens until the file is edited.
  const absl::Status no_admin =
      ParseOperatorTokens("tokens:\n  - {name: otto, role: operator, sha256: " + hash +
                          "}\n  - {name: vic, role: viewer, sha256: " + Sha256Hex("v") + "}\n")
          .status();
  EXPECT_EQ(no_admin.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(no_admin.message(), HasSubstr("no token of role admin"));
  EXPECT_THAT(ParseOperatorTokens("tokens: []").status().message(),
              HasSubstr("no token of role admin"));
  // A key that is itself a mapping (found by fuzz_operator_tokens: yaml-cpp threw).
  EXPECT_EQ(ParseOperatorTokens("tokens:\n  - {name: a, {x: 1}: admin}\n").status().code(),
            absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace fleetnav::server
