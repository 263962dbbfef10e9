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
#include "load_stops.hpp"

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

TEST(StopLatencyTest, EachAgentsFirstStopHeardInARoundIsMatchedToIt) {
  // Round 0 called at 100, returned at 110; round 1 at 200 (returned 230); round 2 failed.
  const std::vector<StopRound> rounds = {
      {100, 110, true, ""}, {200, 230, true, ""}, {300, 301, false, "refused"}};
  // Agent 0 heard round 0 twice (the first counts) and round 1; agent 1 only round 1, before
  // its return; a sample before any round and one of an unknown agent are ignored.
  const StopLatency latency =
      MeasureStopLatency(rounds, {{0, 105}, {0, 150}, {0, 240}, {1, 220}, {1, 50}, {7, 120}}, 2);
  EXPECT_EQ(latency.heard, 3);
  EXPECT_EQ(latency.missed, 1);  // agent 1 in round 0; the failed round is not counted
  ASSERT_EQ(latency.from_return_ms.size(), 3u);
  EXPECT_DOUBLE_EQ(latency.from_return_ms[0], -5e-6);   // heard 5 ns before the return
  EXPECT_DOUBLE_EQ(latency.from_return_ms[1], 10e-6);   // agent 0, round 1
  EXPECT_DOUBLE_EQ(latency.from_return_ms[2], -10e-6);  // agent 1, round 1
  ASSERT_EQ(latency.rpc_ms.size(), 2u);
  EXPECT_DOUBLE_EQ(latency.rpc_ms[1], 30e-6);
}

TEST_F(LoadWorkerTest, EveryAgentHearsEveryStopOfTheWholeFleet) {
  WorkerParams params;
  params.target.address = address_;
  params.agents = 6;
  params.indices = {0, 1, 2, 3, 4, 5};
  LoadWorker worker(params);
  ASSERT_EQ(worker.Connect(SteadyNowNs() + 30'000'000'000), 6);
  const int64_t start_ns = SteadyNowNs();
  const int64_t every_ns = 400'000'000;
  std::vector<StopRound> rounds;
  std::thread stopper([&] { rounds = RunStopRounds(params.target, 2, start_ns, every_ns); });
  worker.Run(start_ns, start_ns + 2 * every_ns, 50'000'000, start_ns + 3 * every_ns);
  stopper.join();
  const WorkerReport report = worker.TakeReport();
  ASSERT_EQ(rounds.size(), 2u);
  for (const StopRound& round : rounds) {
    EXPECT_TRUE(round.ok) << round.error;
    EXPECT_GE(round.return_ns, round.call_ns);
  }
  const StopLatency latency = MeasureStopLatency(rounds, report.stops_heard, 6);
  EXPECT_EQ(latency.heard, 12);
  EXPECT_EQ(latency.missed, 0);
  EXPECT_EQ(latency.from_return_ms.size(), 12u);
  // Both stops were cleared: none in force.
  const absl::StatusOr<std::vector<RobotStop>> in_force = server_->app().stops().InForce();
  ASSERT_TRUE(in_force.ok()) << in_force.status();
  EXPECT_TRUE(in_force->empty());
  worker.Stop();
}

}  // namespace
}  // namespace fleetnav::loadgen
