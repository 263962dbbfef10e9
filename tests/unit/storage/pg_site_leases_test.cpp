// Site leases on a real PostgreSQL: one holder at a time, takeover only after the lease ran
// out, the epoch as fencing token of the old leader's store, and a takeover that waits for the
// old leader's transaction in flight.
#include "fleetnav/storage/postgres/pg_site_leases.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "absl/synchronization/notification.h"
#include "fleetnav/core/status_macros.hpp"
#include "fleetnav/storage/postgres/pg_schema.hpp"
#include "postgres_server.hpp"

namespace fleetnav::storage {
namespace {

using ::testing::HasSubstr;

std::string NewDatabase() {
  absl::StatusOr<std::string> uri = fleetnav::testing::NewSharedDatabase("lease");
  EXPECT_TRUE(uri.ok()) << uri.status();
  return uri.value_or("");
}

std::unique_ptr<PgDatabase> Open(const std::string& uri, std::optional<PgFence> fence = {}) {
  PgOpenOptions options;
  options.fence = std::move(fence);
  absl::StatusOr<std::unique_ptr<PgDatabase>> db =
      PgDatabase::Open(uri, PostgresFleetSchemaMigrations(), options);
  EXPECT_TRUE(db.ok()) << db.status();
  return db.ok() ? *std::move(db) : nullptr;
}

/// One write through `db`: a row in a table of its own.
absl::Status WriteRow(PgDatabase& db, int64_t value) {
  return db.Transaction([&]() -> absl::Status {
    absl::StatusOr<SqlStatement> insert = db.Prepare("INSERT INTO fence_probe (value) VALUES (?)");
    if (!insert.ok()) return insert.status();
    insert->Bind(1, value);
    return insert->Run();
  });
}

int64_t CountProbeRows(PgDatabase& db) {
  int64_t count = -1;
  EXPECT_TRUE(db.Transaction([&]() -> absl::Status {
                  absl::StatusOr<SqlStatement> query =
                      db.Prepare("SELECT COUNT(*) FROM fence_probe");
                  if (!query.ok()) return query.status();
                  if (absl::StatusOr<bool> row = query->Step(); !row.ok()) return row.status();
                  count = query->ColumnInt(0);
                  return absl::OkStatus();
                }).ok());
  return count;
}

void CreateProbeTable(PgDatabase& db) {
  ASSERT_TRUE(db.Transaction([&]() -> absl::Status {
                  absl::StatusOr<SqlStatement> create =
                      db.Prepare("CREATE TABLE fence_probe (value BIGINT NOT NULL)");
                  if (!create.ok()) return create.status();
                  return create->Run();
                }).ok());
}

/// A site led by replica "a" at epoch 1 (its store fenced), on a lease of 0.2 s, with a table
/// `fence_probe` to write to.
struct LedSite {
  std::string uri;
  std::unique_ptr<PgDatabase> lease_db;
  std::unique_ptr<PgSiteLeases> leases;
  std::unique_ptr<PgDatabase> leader;
};

LedSite LeadSite() {
  LedSite site;
  site.uri = NewDatabase();
  site.lease_db = Open(site.uri);
  if (site.lease_db == nullptr) return site;
  CreateProbeTable(*site.lease_db);
  site.leases = std::make_unique<PgSiteLeases>(site.lease_db.get(), /*ttl_s=*/0.2);
  absl::StatusOr<std::optional<int64_t>> first = site.leases->TryAcquire("barn", "a", "a:1");
  EXPECT_TRUE(first.ok() && first->has_value());
  if (first.ok() && first->has_value()) site.leader = Open(site.uri, PgFence{"barn", **first});
  return site;
}

TEST(PgSiteLeasesTest, OneHolderAtATimeAndTakeoverOnlyAfterTheLeaseRanOut) {
  const std::string uri = NewDatabase();
  std::unique_ptr<PgDatabase> db = Open(uri);
  ASSERT_NE(db, nullptr);
  PgSiteLeases leases(db.get(), /*ttl_s=*/0.5);

  absl::StatusOr<std::optional<SiteLease>> none = leases.Current("barn");
  ASSERT_TRUE(none.ok()) << none.status();
  EXPECT_FALSE(none->has_value());

  absl::StatusOr<std::optional<int64_t>> first = leases.TryAcquire("barn", "a", "10.0.0.1:7001");
  ASSERT_TRUE(first.ok()) << first.status();
  ASSERT_TRUE(first->has_value());
  EXPECT_EQ(**first, 1);
  // Held and running: another replica does not get it, nor a second site's lease its epoch.
  absl::StatusOr<std::optional<int64_t>> refused = leases.TryAcquire("barn", "b", "10.0.0.2:7001");
  ASSERT_TRUE(refused.ok()) << refused.status();
  EXPECT_FALSE(refused->has_value());
  absl::StatusOr<std::optional<int64_t>> other = leases.TryAcquire("store", "b", "10.0.0.2:7001");
  ASSERT_TRUE(other.ok() && other->has_value());
  EXPECT_EQ(**other, 1);

  absl::StatusOr<std::optional<SiteLease>> held = leases.Current("barn");
  ASSERT_TRUE(held.ok() && held->has_value());
  EXPECT_EQ((*held)->holder, "a");
  EXPECT_EQ((*held)->address, "10.0.0.1:7001");
  EXPECT_FALSE((*held)->expired);

  // Renewed, it outlives its first term.
  for (int i = 0; i < 4; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    ASSERT_TRUE(leases.Renew("barn", "a", 1).ok());
  }
  refused = leases.TryAcquire("barn", "b", "10.0.0.2:7001");
  ASSERT_TRUE(refused.ok());
  EXPECT_FALSE(refused->has_value());

  // Left to run out, it is taken over with the next epoch, and the old holder cannot renew.
  std::this_thread::sleep_for(std::chrono::milliseconds(700));
  absl::StatusOr<std::optional<SiteLease>> expired = leases.Current("barn");
  ASSERT_TRUE(expired.ok() && expired->has_value());
  EXPECT_TRUE((*expired)->expired);
  absl::StatusOr<std::optional<int64_t>> second = leases.TryAcquire("barn", "b", "10.0.0.2:7001");
  ASSERT_TRUE(second.ok() && second->has_value());
  EXPECT_EQ(**second, 2);
  const absl::Status lost = leases.Renew("barn", "a", 1);
  EXPECT_EQ(lost.code(), absl::StatusCode::kFailedPrecondition) << lost;
  EXPECT_TRUE(leases.Renew("barn", "b", 2).ok());
}

TEST(PgSiteLeasesTest, AFencedStoreWritesNothingOnceItsEpochWasTakenOver) {
  LedSite site = LeadSite();
  ASSERT_NE(site.leader, nullptr);
  const std::string& uri = site.uri;
  PgDatabase* lease_db = site.lease_db.get();
  PgSiteLeases& leases = *site.leases;
  PgDatabase* leader = site.leader.get();
  ASSERT_TRUE(WriteRow(*leader, 1).ok());

  // The old leader paused past its lease: another replica took the site over.
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  absl::StatusOr<std::optional<int64_t>> second = leases.TryAcquire("barn", "b", "b:1");
  ASSERT_TRUE(second.ok() && second->has_value());

  const absl::Status fenced = WriteRow(*leader, 2);
  EXPECT_EQ(fenced.code(), absl::StatusCode::kFailedPrecondition) << fenced;
  EXPECT_THAT(fenced.message(), HasSubstr("lease is at epoch 2"));
  EXPECT_EQ(CountProbeRows(*lease_db), 1);

  // A fenced store with a bad site name is refused at open.
  PgOpenOptions bad;
  bad.fence = PgFence{"barn'; DROP TABLE jobs; --", 1};
  absl::StatusOr<std::unique_ptr<PgDatabase>> refused =
      PgDatabase::Open(uri, PostgresFleetSchemaMigrations(), bad);
  EXPECT_EQ(refused.status().code(), absl::StatusCode::kInvalidArgument) << refused.status();
}

TEST(PgSiteLeasesTest, ATakeoverWaitsForTheOldLeadersTransactionInFlight) {
  LedSite site = LeadSite();
  ASSERT_NE(site.leader, nullptr);
  PgDatabase* lease_db = site.lease_db.get();
  PgSiteLeases& leases = *site.leases;
  PgDatabase* leader = site.leader.get();

  // The old leader's transaction passed its fence check and is still running when its lease
  // runs out and another replica tries to take over.
  absl::Notification inside;
  absl::Notification finish;
  std::thread old_leader([&] {
    EXPECT_TRUE(leader
                    ->Transaction([&]() -> absl::Status {
                      absl::StatusOr<SqlStatement> insert =
                          leader->Prepare("INSERT INTO fence_probe (value) VALUES (7)");
                      if (!insert.ok()) return insert.status();
                      RETURN_IF_ERROR(insert->Run());
                      inside.Notify();
                      finish.WaitForNotification();
                      return absl::OkStatus();
                    })
                    .ok());
  });
  inside.WaitForNotification();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  std::atomic<bool> taken{false};
  std::thread takeover([&] {
    absl::StatusOr<std::optional<int64_t>> second = leases.TryAcquire("barn", "b", "b:1");
    EXPECT_TRUE(second.ok() && second->has_value());
    taken = true;
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_FALSE(taken.load()) << "the takeover did not wait for the old leader's transaction";
  finish.Notify();
  old_leader.join();
  takeover.join();
  EXPECT_TRUE(taken.load());
  // The write that was in flight before the takeover landed; the next one is fenced.
  EXPECT_EQ(CountProbeRows(*lease_db), 1);
  EXPECT_EQ(WriteRow(*leader, 8).code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_EQ(CountProbeRows(*lease_db), 1);
}

}  // namespace
}  // namespace fleetnav::storage
