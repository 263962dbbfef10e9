// OperatorTokenService over the in-memory token store: what it installs in the gate after
// each change, and that a refused or failed change neither stores nor installs anything.
#include "fleetnav/server/access/operator_tokens.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "fleetnav/storage/memory/memory_fleet_repositories.hpp"

namespace fleetnav::server {
namespace {

using ::testing::HasSubstr;

constexpr absl::string_view kMethodOfOperators = "/fleetnav.v1.FleetService/SubmitJob";

/// A token store whose writes can be made to fail, as a lost disk would.
class FlakyTokenStore final : public storage::OperatorTokenRepository {
 public:
  absl::Status InsertToken(const storage::StoredOperatorToken& token) override {
    if (fail_writes) return absl::UnavailableError("disk gone");
    return inner.InsertToken(token);
  }
  absl::StatusOr<std::vector<storage::StoredOperatorToken>> ListTokens() override {
    return inner.ListTokens();
  }
  absl::Status DeleteToken(const std::string& name) override {
    if (fail_writes) return absl::UnavailableError("disk gone");
    return inner.DeleteToken(name);
  }
  bool fail_writes = false;
  storage::MemoryOperatorTokenRepository inner;
};

class OperatorTokensTest : public ::testing::Test {
 protected:
  OperatorTokensTest()
      : clock_(0, 1'700'000'000'000),
        service_(&store_, {{"ops", Role::kAdmin, Sha256Hex("file-secret")}}, &clock_,
                 [this](std::shared_ptr<const AccessPolicy> policy) {
                   policy_ = std::move(policy);
                   ++installs_;
                 }) {}

  /// How the installed policy answers a call to an operator's method with `secret`.
  absl::StatusCode Check(const std::string& secret) const {
    return policy_->Authorize(kMethodOfOperators, {"Bearer " + secret, ""}).status().code();
  }

  FlakyTokenStore store_;
  ManualClock clock_;
  std::shared_ptr<const AccessPolicy> policy_;
  int installs_ = 0;
  OperatorTokenService service_;
};

TEST_F(OperatorTokensTest, ACreatedTokenIsAdmittedWithItsRoleAndOnlyItsHashIsStored) {
  ASSERT_TRUE(service_.Load().ok());
  absl::StatusOr<IssuedToken> night = service_.Create("night-shift", Role::kOperator);
  ASSERT_TRUE(night.ok()) << night.status();
  EXPECT_EQ(night->secret.size(), 64u);
  EXPECT_EQ(night->created_unix_ms, 1'700'000'000'000);
  EXPECT_EQ(Check(night->secret), absl::StatusCode::kOk);
  EXPECT_EQ(Check("file-secret"), absl::StatusCode::kOk);
  EXPECT_EQ(
      policy_->Authorize("/fleetnav.v1.FleetService/DeleteMap", {"Bearer " + night->secret, ""})
          .status()
          .code(),
      absl::StatusCode::kPermissionDenied);
  absl::StatusOr<std::vector<storage::StoredOperatorToken>> stored = store_.ListTokens();
  ASSERT_TRUE(stored.ok());
  ASSERT_EQ(stored->size(), 1u);
  EXPECT_EQ((*stored)[0].token.sha256_hex, Sha256Hex(night->secret));
  // Two tokens never share a secret.
  absl::StatusOr<IssuedToken> other = service_.Create("other", Role::kViewer);
  ASSERT_TRUE(other.ok());
  EXPECT_NE(other->secret, night->secret);
}

TEST_F(OperatorTokensTest, ListShowsTheFileThenTheStoreWithoutSecrets) {
  ASSERT_TRUE(service_.Load().ok());
  ASSERT_TRUE(service_.Create("zeta", Role::kViewer).ok());
  ASSERT_TRUE(service_.Create("alpha", Role::kAdmin).ok());
  const std::vector<TokenListing> listed = service_.List();
  ASSERT_EQ(listed.size(), 3u);
  EXPECT_EQ(listed[0].name, "ops");
  EXPECT_EQ(listed[0].source, TokenSource::kFile);
  EXPECT_EQ(listed[1].name, "alpha");
  EXPECT_EQ(listed[1].role, Role::kAdmin);
  EXPECT_EQ(listed[1].source, TokenSource::kStore);
  EXPECT_EQ(listed[2].name, "zeta");
}

TEST_F(OperatorTokensTest, BadNamesAndTakenNamesAreRefusedAndNothingChanges) {
  ASSERT_TRUE(service_.Load().ok());
  const int installs = installs_;
  for (const std::string& name :
       std::vector<std::string>{"", "a b", "semi;colon", std::string(65, 'x'), "ünï"}) {
    const absl::StatusOr<IssuedToken> made = service_.Create(name, Role::kViewer);
    EXPECT_EQ(made.status().code(), absl::StatusCode::kInvalidArgument) << name;
    EXPECT_THAT(made.status().message(), HasSubstr("token name"));
  }
  EXPECT_EQ(service_.Create("ops", Role::kViewer).status().code(),
            absl::StatusCode::kAlreadyExists);
  ASSERT_TRUE(service_.Create("night", Role::kViewer).ok());
  EXPECT_EQ(service_.Create("night", Role::kAdmin).status().code(),
            absl::StatusCode::kAlreadyExists);
  EXPECT_EQ(installs_, installs + 1);
  EXPECT_EQ(store_.ListTokens()->size(), 1u);
}

TEST_F(OperatorTokensTest, RevokingRefusesTheTokenAtOnceAndTheFileTokensStay) {
  ASSERT_TRUE(service_.Load().ok());
  absl::StatusOr<IssuedToken> night = service_.Create("night", Role::kOperator);
  ASSERT_TRUE(night.ok());
  ASSERT_TRUE(service_.Revoke("night").ok());
  EXPECT_EQ(Check(night->secret), absl::StatusCode::kUnauthenticated);
  EXPECT_TRUE(store_.ListTokens()->empty());
  EXPECT_EQ(service_.Revoke("night").code(), absl::StatusCode::kNotFound);
  const absl::Status file = service_.Revoke("ops");
  EXPECT_EQ(file.code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_THAT(file.message(), HasSubstr("token file"));
  EXPECT_EQ(Check("file-secret"), absl::StatusCode::kOk);
}

TEST_F(OperatorTokensTest, AStoreThatCannotWriteLeavesTheGateAsItWas) {
  ASSERT_TRUE(service_.Load().ok());
  absl::StatusOr<IssuedToken> night = service_.Create("night", Role::kOperator);
  ASSERT_TRUE(night.ok());
  const int installs = installs_;
  store_.fail_writes = true;
  EXPECT_EQ(service_.Create("day", Role::kOperator).status().code(),
            absl::StatusCode::kUnavailable);
  EXPECT_EQ(service_.Revoke("night").code(), absl::StatusCode::kUnavailable);
  EXPECT_EQ(installs_, installs);
  EXPECT_EQ(Check(night->secret), absl::StatusCode::kOk);  // not revoked: the store still has it
  EXPECT_EQ(service_.List().size(), 2u);
}

TEST_F(OperatorTokensTest, LoadReadsTheStoreAndTheFileWinsOverAStoredTokenOfItsName) {
  ASSERT_TRUE(store_.InsertToken({{"kept", Role::kViewer, Sha256Hex("kept-secret")}, 5}).ok());
  ASSERT_TRUE(store_.InsertToken({{"ops", Role::kViewer, Sha256Hex("shadow")}, 6}).ok());
  ASSERT_TRUE(store_.InsertToken({{"copy", Role::kAdmin, Sha256Hex("file-secret")}, 7}).ok());
  absl::StatusOr<std::vector<std::string>> conflicts = service_.Load();
  ASSERT_TRUE(conflicts.ok()) << conflicts.status();
  ASSERT_EQ(conflicts->size(), 2u);
  EXPECT_THAT((*conflicts)[0], HasSubstr("'copy'"));
  EXPECT_THAT((*conflicts)[1], HasSubstr("'ops'"));
  EXPECT_EQ(policy_->Authorize(kMethodOfOperators, {"Bearer kept-secret", ""}).status().code(),
            absl::StatusCode::kPermissionDenied);  // a viewer
  EXPECT_EQ(Check("shadow"), absl::StatusCode::kUnauthenticated);
  EXPECT_EQ(Check("file-secret"), absl::StatusCode::kOk);
  EXPECT_EQ(service_.List().size(), 2u);
}

}  // namespace
}  // namespace fleetnav::server
