// PoseHistoryRepository conformance over SQLite and memory.
#include <gtest/gtest.h>

#include <filesystem>
#include <memory>

#include "fleetnav/storage/memory/memory_fleet_repositories.hpp"
#include "fleetnav/storage/sqlite/schema.hpp"
#include "fleetnav/storage/sqlite/sqlite_fleet_repositories.hpp"
#include "temp_db_path.hpp"

namespace fleetnav::storage {
namespace {

class PoseHistoryTest : public ::testing::TestWithParam<bool> {
 protected:
  void SetUp() override {
    if (GetParam()) {
      path_ = std::make_unique<testing::TempDbPath>();
      auto db = SqliteDatabase::Open(path_->path(), FleetSchemaMigrations());
      ASSERT_TRUE(db.ok()) << db.status();
      db_ = std::move(*db);
      repository_ = std::make_unique<SqlitePoseHistoryRepository>(db_.get());
    } else {
      repository_ = std::make_unique<MemoryPoseHistoryRepository>();
    }
  }
  void TearDown() override {
    repository_.reset();
    db_.reset();
    path_.reset();
  }
  std::unique_ptr<testing::TempDbPath> path_;
  std::unique_ptr<SqliteDatabase> db_;
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

INSTANTIATE_TEST_SUITE_P(Repositories, PoseHistoryTest, ::testing::Values(true, false),
                         [](const auto& info) { return info.param ? "Sqlite" : "Memory"; });

}  // namespace
}  // namespace fleetnav::storage
