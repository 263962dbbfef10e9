// PoseHistoryRepository conformance over SQLite, PostgreSQL and memory.
#include <gtest/gtest.h>

#include <filesystem>
#include <memory>

#include "fleetnav/storage/memory/memory_fleet_repositories.hpp"
#include "fleetnav/storage/sql/sql_fleet_repositories.hpp"
#include "test_database.hpp"

namespace fleetnav::storage {
namespace {

using testing::Backend;

class PoseHistoryTest : public ::testing::TestWithParam<Backend> {
 protected:
  void SetUp() override {
    if (GetParam() != Backend::kMemory) {
      db_ = std::make_unique<testing::TestDatabase>(GetParam());
      ASSERT_NE(db_->get(), nullptr);
      repository_ = std::make_unique<SqlPoseHistoryRepository>(db_->get());
    } else {
      repository_ = std::make_unique<MemoryPoseHistoryRepository>();
    }
  }
  void TearDown() override {
    repository_.reset();
    db_.reset();
  }
  std::unique_ptr<testing::TestDatabase> db_;
  std::unique_ptr<PoseHistoryRepository> repository_;
};

TEST_P(PoseHistoryTest, SamplesComeBackPerRobotOldestFirstAndArePruned) {
  std::vector<PoseSample> batch;
  for (int i = 0; i < 5; ++i) {
    batch.push_back({"a", 1000 * i, 10 * i, Pose2(i, 2.0 * i, 0.1 * i)});
    batch.push_back({"b", 1000 * i, 10 * i, Pose2(-i, 0, 0)});
  }
  ASSERT_TRUE(repository_->AppendPoses(batch).ok());
  absl::StatusOr<std::vector<PoseSample>> a = repository_->ListPoses("a", 2000, 100);
  ASSERT_TRUE(a.ok());
  ASSERT_EQ(a->size(), 3u);
  EXPECT_EQ((*a)[0].unix_ms, 2000);
  EXPECT_DOUBLE_EQ((*a)[2].pose_in_map.y_m(), 8.0);
  EXPECT_EQ((*a)[2].stamp_ns, 40);
  EXPECT_EQ(repository_->ListPoses("a", 0, 2)->size(), 2u);
  EXPECT_TRUE(repository_->ListPoses("nobody", 0, 10)->empty());
  absl::StatusOr<int64_t> pruned = repository_->PruneBefore(3000);
  ASSERT_TRUE(pruned.ok());
  EXPECT_EQ(*pruned, 6);
  EXPECT_EQ(repository_->ListPoses("b", 0, 100)->size(), 2u);
}

INSTANTIATE_TEST_SUITE_P(Repositories, PoseHistoryTest,
                         ::testing::Values(Backend::kSqlite, Backend::kPostgres, Backend::kMemory),
                         testing::BackendTestName);

}  // namespace
}  // namespace fleetnav::storage
