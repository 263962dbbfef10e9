// fleetnav-loadgen's pacing and accounting: the even spread of due times, nearest-rank
// percentiles, and one LoadWorker against a real fleetnavd on loopback (counts, not times).
#include "load_agents.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <thread>

#include "fleetnav/server/rpc/fleet_server.hpp"
#include "integration/test_paths.hpp"
#include "load_report.hpp"

namespace fleetnav::loadgen {
namespace {

TEST(DueOffsetTest, SpreadsAgentsEvenlyOverThePeriodInIndexOrder) {
  constexpr int64_t kPeriodNs = 100'000'000;
  EXPECT_EQ(DueOffsetNs(0, 4, kPeriodNs), 0);
  EXPECT_EQ(DueOffsetNs(1, 4, kPeriodNs), 25'000'000);
  EXPECT_EQ(DueOffsetNs(3, 4, kPeriodNs), 75'000'000);
  int64_t previous = -1;
  for (int i = 0; i < 5000; ++i) {
    const int64_t offset = DueOffsetNs(i, 5000, kPeriodNs);
    EXPECT_GT(offset, previous);
    EXPECT_LT(offset, kPeriodNs);
    previous = offset;
  }
  EXPECT_EQ(DueOffsetNs(0, 0, kPeriodNs), 0);  // no agents: no division by zero
}

TEST(PercentileTest, IsTheNearestRank) {
  EXPECT_EQ(Percentile({}, 50), 0.0);
  EXPECT_EQ(Percentile({3, 1, 2}, 50), 2.0);
  EXPECT_EQ(Percentile({3, 1, 2}, 100), 3.0);
  EXPECT_EQ(Percentile({3, 1, 2}, 0), 1.0);
  std::vector<double> hundred;
  for (int i = 1; i <= 100; ++i) hundred.push_back(i);
  EXPECT_EQ(Percentile(hundred, 99), 99.0);
}

class LoadWorkerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    db_path_ = testing::UniqueTempPath("loadgen") + ".db";
    server::FleetServerParams params;
    params.listen_address = "127.0.0.1:0";
    params.db_path = db_path_;
    server_ = std::make_unique<server::FleetServer>(params);
    absl::StatusOr<int> port = server_->Start();
    ASSERT_TRUE(port.ok()) << port.status();
    address_ = "127.0.0.1:" + std::to_string(*port);
  }
  void TearDown() override {
    server_->Shutdown();
    server_.reset();
    std::filesystem::remove(db_path_);
  }

  std::string db_path_;
  std::string address_;
  std::unique_ptr<server::FleetServer> server_;
};

TEST_F(LoadWorkerTest, AgentsRegisterAndEveryDueMessageIsDeliveredOrCountedAsSkipped) {
  WorkerParams params;
  params.target.address = address_;
  params.agents = 12;
  params.indices = {1, 3, 5, 7, 9, 11};  // the odd half of a 12-agent run
  params.streams_per_connection = 4;     // two connections
  LoadWorker worker(params);
  ASSERT_EQ(worker.Connect(SteadyNowNs() + 30'000'000'000), 6);
  for (const int i : params.indices) {
    EXPECT_TRUE(server_->app().registry().Get("load-" + std::to_string(i)).ok()) << i;
  }
  EXPECT_FALSE(server_->app().registry().Get("load-0").ok());

  const int64_t start_ns = SteadyNowNs();
  const int64_t period_ns = 20'000'000;  // 50 Hz for 10 periods
  const int64_t end_ns = start_ns + 10 * period_ns;
  worker.Run(start_ns, end_ns, period_ns, end_ns + 2'000'000'000);
  const WorkerReport report = worker.TakeReport();
  EXPECT_EQ(report.connected, 6);
  EXPECT_EQ(report.scheduled, 60u);
  EXPECT_EQ(report.delivered + report.skipped, report.scheduled);
  EXPECT_EQ(report.lag_ms.size(), report.delivered);
  for (double lag_ms : report.lag_ms) EXPECT_GE(lag_ms, 0.0);

  // What was delivered reaches the server's registry (the server may still be reading it).
  auto recorded = [&] {
    uint64_t count = 0;
    for (const int i : params.indices) {
      absl::StatusOr<RobotRecord> record =
          server_->app().registry().Get("load-" + std::to_string(i));
      if (record.ok()) count += record->telemetry_count;
    }
    return count;
  };
  for (int i = 0; i < 500 && recorded() < report.delivered; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_EQ(recorded(), report.delivered);
  worker.Stop();
}

}  // namespace
}  // namespace fleetnav::loadgen
