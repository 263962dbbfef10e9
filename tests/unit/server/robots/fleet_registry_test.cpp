#include "fleetnav/server/robots/fleet_registry.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <thread>
#include <vector>

namespace fleetnav::server {
namespace {

using ::testing::HasSubstr;

constexpr int64_t kSecondNs = 1'000'000'000;

RobotIdentity Identity(const std::string& robot_id, const std::string& version = "1.0") {
  RobotIdentity identity;
  identity.robot_id = robot_id;
  identity.model = LelyVectorModel();
  identity.capabilities = {"feed"};
  identity.software_version = version;
  return identity;
}

Telemetry TelemetryAt(uint64_t sequence, double x_m) {
  Telemetry telemetry;
  telemetry.sequence = sequence;
  telemetry.stamp_ns = static_cast<int64_t>(sequence) * 100'000'000;
  telemetry.pose_in_map = Pose2(x_m, 1.0, 0.5);
  telemetry.battery_fraction = 0.8;
  telemetry.job_id = "job-1";
  return telemetry;
}

class FleetRegistryTest : public ::testing::Test {
 protected:
  FleetRegistryTest() : clock_(100 * kSecondNs), registry_(&clock_, FleetRegistryParams{}) {}

  RobotRecord GetOrDie(const std::string& robot_id) {
    absl::StatusOr<RobotRecord> record = registry_.Get(robot_id);
    EXPECT_TRUE(record.ok()) << record.status();
    return record.ok() ? *record : RobotRecord{};
  }

  ManualClock clock_;
  FleetRegistry registry_;
};

TEST_F(FleetRegistryTest, ConnectMakesTheRobotOnline) {
  registry_.Connect(Identity("vector-1", "2.3.4"));
  const RobotRecord record = GetOrDie("vector-1");
  EXPECT_EQ(record.connection, ConnectionState::kOnline);
  EXPECT_EQ(record.identity.robot_id, "vector-1");
  EXPECT_EQ(record.identity.software_version, "2.3.4");
  EXPECT_EQ(record.identity.model.kind_name, "lely-vector");
  EXPECT_EQ(record.last_seen_ns, 100 * kSecondNs);
  EXPECT_FALSE(record.last_telemetry.has_value());
  EXPECT_EQ(record.telemetry_count, 0u);
  EXPECT_GT(record.revision, 0u);
}

TEST_F(FleetRegistryTest, SessionsAreDistinct) {
  const uint64_t a = registry_.Connect(Identity("a"));
  const uint64_t b = registry_.Connect(Identity("b"));
  const uint64_t a2 = registry_.Connect(Identity("a"));
  EXPECT_NE(a, b);
  EXPECT_NE(a, a2);
  EXPECT_NE(b, a2);
}

TEST_F(FleetRegistryTest, RecordTelemetryUpdatesLastTelemetryAndCount) {
  const uint64_t session = registry_.Connect(Identity("vector-1"));
  clock_.AdvanceNs(kSecondNs / 2);
  ASSERT_TRUE(registry_.RecordTelemetry("vector-1", session, TelemetryAt(1, 2.0)).ok());
  clock_.AdvanceNs(kSecondNs / 2);
  ASSERT_TRUE(registry_.RecordTelemetry("vector-1", session, TelemetryAt(2, 2.5)).ok());

  const RobotRecord record = GetOrDie("vector-1");
  EXPECT_EQ(record.connection, ConnectionState::kOnline);
  EXPECT_EQ(record.telemetry_count, 2u);
  ASSERT_TRUE(record.last_telemetry.has_value());
  EXPECT_EQ(record.last_telemetry->sequence, 2u);
  EXPECT_NEAR(record.last_telemetry->pose_in_map.x_m(), 2.5, 1e-12);
  EXPECT_EQ(record.last_telemetry->job_id, "job-1");
  EXPECT_EQ(record.last_seen_ns, 101 * kSecondNs);
}

TEST_F(FleetRegistryTest, TimeHeldByTrafficCountsOnlyWhileTheRobotStandsHeld) {
  const uint64_t session = registry_.Connect(Identity("vector-1"));
  Telemetry standing = TelemetryAt(1, 0.0);
  standing.mode = NavigationMode::kIdle;
  Telemetry driving = TelemetryAt(2, 0.0);
  driving.mode = NavigationMode::kStripeReactive;
  const auto held_s = [&] { return GetOrDie("vector-1").traffic_held_s; };

  clock_.AdvanceNs(kSecondNs);
  ASSERT_TRUE(registry_.RecordTelemetry("vector-1", session, standing).ok());
  EXPECT_EQ(held_s(), 0.0);  // standing, but nothing holds it
  registry_.SetTrafficWait("vector-1", "waits for lely2");
  clock_.AdvanceNs(kSecondNs / 10);
  ASSERT_TRUE(registry_.RecordTelemetry("vector-1", session, standing).ok());
  clock_.AdvanceNs(kSecondNs / 10);
  ASSERT_TRUE(registry_.RecordTelemetry("vector-1", session, standing).ok());
  EXPECT_NEAR(held_s(), 0.2, 1e-9);
  clock_.AdvanceNs(kSecondNs / 10);
  ASSERT_TRUE(registry_.RecordTelemetry("vector-1", session, driving).ok());
  EXPECT_NEAR(held_s(), 0.2, 1e-9);  // still cleared for what it drives
  registry_.SetTrafficWait("vector-1", "");
  clock_.AdvanceNs(kSecondNs);
  ASSERT_TRUE(registry_.RecordTelemetry("vector-1", session, standing).ok());
  EXPECT_NEAR(held_s(), 0.2, 1e-9);
}

TEST_F(FleetRegistryTest, SilentRobotBecomesStaleAndTelemetryBringsItBack) {
  const uint64_t session = registry_.Connect(Identity("vector-1"));
  ASSERT_TRUE(registry_.RecordTelemetry("vector-1", session, TelemetryAt(1, 0.0)).ok());

  clock_.AdvanceNs(2 * kSecondNs);  // exactly stale_after_s: not yet stale
  EXPECT_EQ(GetOrDie("vector-1").connection, ConnectionState::kOnline);
  ASSERT_EQ(registry_.Snapshot().size(), 1u);
  EXPECT_EQ(registry_.Snapshot()[0].connection, ConnectionState::kOnline);

  clock_.AdvanceNs(1'000'000);  // 2.001 s without telemetry
  std::vector<RobotRecord> snapshot = registry_.Snapshot();
  ASSERT_EQ(snapshot.size(), 1u);
  EXPECT_EQ(snapshot[0].connection, ConnectionState::kStale);
  EXPECT_EQ(GetOrDie("vector-1").connection, ConnectionState::kStale);

  ASSERT_TRUE(registry_.RecordTelemetry("vector-1", session, TelemetryAt(2, 0.1)).ok());
  snapshot = registry_.Snapshot();
  ASSERT_EQ(snapshot.size(), 1u);
  EXPECT_EQ(snapshot[0].connection, ConnectionState::kOnline);
}

TEST_F(FleetRegistryTest, StaleThresholdFollowsTheParams) {
  FleetRegistry registry(&clock_, FleetRegistryParams{0.25});
  registry.Connect(Identity("vector-1"));
  clock_.AdvanceNs(200'000'000);
  EXPECT_EQ(registry.Snapshot()[0].connection, ConnectionState::kOnline);
  clock_.AdvanceNs(100'000'000);
  EXPECT_EQ(registry.Snapshot()[0].connection, ConnectionState::kStale);
}

TEST_F(FleetRegistryTest, ConnectedRobotWithoutTelemetryAlsoGoesStale) {
  registry_.Connect(Identity("vector-1"));
  clock_.AdvanceNs(3 * kSecondNs);
  EXPECT_EQ(GetOrDie("vector-1").connection, ConnectionState::kStale);
}

TEST_F(FleetRegistryTest, DisconnectMarksOfflineAndOfflineNeverTurnsStale) {
  const uint64_t session = registry_.Connect(Identity("vector-1"));
  ASSERT_TRUE(registry_.RecordTelemetry("vector-1", session, TelemetryAt(1, 0.0)).ok());
  registry_.Disconnect("vector-1", session);
  EXPECT_EQ(GetOrDie("vector-1").connection, ConnectionState::kOffline);
  clock_.AdvanceNs(60 * kSecondNs);
  const RobotRecord record = GetOrDie("vector-1");
  EXPECT_EQ(record.connection, ConnectionState::kOffline);
  // The last report is kept for operators.
  ASSERT_TRUE(record.last_telemetry.has_value());
  EXPECT_EQ(record.last_telemetry->sequence, 1u);
}

TEST_F(FleetRegistryTest, SecondConnectReplacesTheFirstSession) {
  const uint64_t old_session = registry_.Connect(Identity("vector-1", "1.0"));
  ASSERT_TRUE(registry_.RecordTelemetry("vector-1", old_session, TelemetryAt(1, 0.0)).ok());
  const uint64_t new_session = registry_.Connect(Identity("vector-1", "1.1"));
  ASSERT_NE(old_session, new_session);
  EXPECT_EQ(GetOrDie("vector-1").identity.software_version, "1.1");

  // The old stream's telemetry is refused so that it ends ...
  const absl::Status refused =
      registry_.RecordTelemetry("vector-1", old_session, TelemetryAt(2, 9.0));
  EXPECT_EQ(refused.code(), absl::StatusCode::kFailedPrecondition) << refused;
  EXPECT_THAT(std::string(refused.message()), HasSubstr("vector-1"));
  RobotRecord record = GetOrDie("vector-1");
  ASSERT_TRUE(record.last_telemetry.has_value());
  EXPECT_EQ(record.last_telemetry->sequence, 1u);
  EXPECT_EQ(record.telemetry_count, 1u);

  // ... and its disconnect does not take the new session offline.
  registry_.Disconnect("vector-1", old_session);
  EXPECT_EQ(GetOrDie("vector-1").connection, ConnectionState::kOnline);

  ASSERT_TRUE(registry_.RecordTelemetry("vector-1", new_session, TelemetryAt(3, 1.0)).ok());
  record = GetOrDie("vector-1");
  EXPECT_EQ(record.last_telemetry->sequence, 3u);
  EXPECT_EQ(record.telemetry_count, 2u);
  registry_.Disconnect("vector-1", new_session);
  EXPECT_EQ(GetOrDie("vector-1").connection, ConnectionState::kOffline);
}

TEST_F(FleetRegistryTest, ReconnectAfterDisconnectIsOnlineAgain) {
  const uint64_t first = registry_.Connect(Identity("vector-1"));
  registry_.Disconnect("vector-1", first);
  const uint64_t second = registry_.Connect(Identity("vector-1"));
  EXPECT_EQ(GetOrDie("vector-1").connection, ConnectionState::kOnline);
  EXPECT_TRUE(registry_.RecordTelemetry("vector-1", second, TelemetryAt(1, 0.0)).ok());
  EXPECT_EQ(registry_.RecordTelemetry("vector-1", first, TelemetryAt(2, 0.0)).code(),
            absl::StatusCode::kFailedPrecondition);
}

TEST_F(FleetRegistryTest, UnknownRobotIsNotFound) {
  const absl::Status telemetry = registry_.RecordTelemetry("ghost", 1, TelemetryAt(1, 0.0));
  EXPECT_EQ(telemetry.code(), absl::StatusCode::kNotFound) << telemetry;
  EXPECT_THAT(std::string(telemetry.message()), HasSubstr("ghost"));
  const absl::StatusOr<RobotRecord> get = registry_.Get("ghost");
  ASSERT_FALSE(get.ok());
  EXPECT_EQ(get.status().code(), absl::StatusCode::kNotFound);
  EXPECT_THAT(std::string(get.status().message()), HasSubstr("ghost"));
  // Disconnecting an unknown robot is harmless and registers nothing.
  registry_.Disconnect("ghost", 1);
  EXPECT_TRUE(registry_.Snapshot().empty());
}

TEST_F(FleetRegistryTest, SnapshotIsOrderedById) {
  for (const char* id : {"vector-3", "mecanum-1", "vector-10", "ackermann-2"}) {
    registry_.Connect(Identity(id));
  }
  std::vector<std::string> ids;
  for (const RobotRecord& record : registry_.Snapshot()) ids.push_back(record.identity.robot_id);
  EXPECT_THAT(ids, ::testing::ElementsAre("ackermann-2", "mecanum-1", "vector-10", "vector-3"));
}

TEST_F(FleetRegistryTest, IdleOnlineSkipsOfflineStaleAndBusyRobotsAndAsksOnlyAboutTheRest) {
  registry_.RestoreOffline(Identity("a-offline"));
  registry_.Connect(Identity("b-stale"));
  clock_.AdvanceNs(3 * kSecondNs);
  for (const std::string id : {"c-busy", "d-idle", "e-idle", "f-unwanted"}) {
    registry_.Connect(Identity(id));
  }
  registry_.SetCurrentJob("c-busy", "job-1");

  std::vector<std::string> asked;
  const std::vector<RobotRecord> idle = registry_.IdleOnline([&](const RobotRecord& record) {
    asked.push_back(record.identity.robot_id);
    return record.identity.robot_id != "f-unwanted";
  });
  EXPECT_THAT(asked, ::testing::ElementsAre("d-idle", "e-idle", "f-unwanted"));
  ASSERT_EQ(idle.size(), 2u);
  EXPECT_EQ(idle[0].identity.robot_id, "d-idle");
  EXPECT_EQ(idle[1].identity.robot_id, "e-idle");
  EXPECT_EQ(idle[0].connection, ConnectionState::kOnline);
  EXPECT_EQ(idle[0].identity.capabilities, std::vector<std::string>{"feed"});

  registry_.SetCurrentJob("c-busy", "");  // done with its job: idle again
  EXPECT_EQ(registry_.IdleOnline([](const RobotRecord&) { return true; }).size(), 4u);
}

TEST_F(FleetRegistryTest, ChangedSinceReturnsOnlyRobotsChangedAfterARevision) {
  const uint64_t a = registry_.Connect(Identity("a"));
  const uint64_t b = registry_.Connect(Identity("b"));
  registry_.Connect(Identity("c"));

  uint64_t latest = 0;
  EXPECT_EQ(registry_.ChangedSince(0, &latest).size(), 3u);
  const uint64_t after_connects = latest;
  EXPECT_GT(after_connects, 0u);
  EXPECT_TRUE(registry_.ChangedSince(after_connects, &latest).empty());
  EXPECT_EQ(latest, after_connects);

  ASSERT_TRUE(registry_.RecordTelemetry("b", b, TelemetryAt(1, 0.0)).ok());
  std::vector<RobotRecord> changed = registry_.ChangedSince(after_connects, &latest);
  ASSERT_EQ(changed.size(), 1u);
  EXPECT_EQ(changed[0].identity.robot_id, "b");
  EXPECT_EQ(changed[0].telemetry_count, 1u);
  EXPECT_GT(latest, after_connects);
  const uint64_t after_telemetry = latest;

  registry_.Disconnect("a", a);
  changed = registry_.ChangedSince(after_telemetry, &latest);
  ASSERT_EQ(changed.size(), 1u);
  EXPECT_EQ(changed[0].identity.robot_id, "a");
  EXPECT_EQ(changed[0].connection, ConnectionState::kOffline);

  // A refused message from a replaced session is not a change.
  const uint64_t before_refusal = latest;
  registry_.Connect(Identity("b"));
  uint64_t after_reconnect = 0;
  ASSERT_EQ(registry_.ChangedSince(before_refusal, &after_reconnect).size(), 1u);
  EXPECT_FALSE(registry_.RecordTelemetry("b", b, TelemetryAt(2, 0.0)).ok());
  registry_.Disconnect("b", b);
  EXPECT_TRUE(registry_.ChangedSince(after_reconnect, &latest).empty());
  EXPECT_EQ(latest, after_reconnect);
}

TEST_F(FleetRegistryTest, ConcurrentTelemetryIsNotLost) {
  constexpr int kRobots = 4;
  constexpr int kMessages = 250;
  std::vector<uint64_t> sessions;
  for (int r = 0; r < kRobots; ++r)
    sessions.push_back(registry_.Connect(Identity("r" + std::to_string(r))));
  std::vector<std::thread> threads;
  for (int r = 0; r < kRobots; ++r) {
    threads.emplace_back([this, r, session = sessions[r]] {
      for (int i = 1; i <= kMessages; ++i) {
        EXPECT_TRUE(registry_
                        .RecordTelemetry("r" + std::to_string(r), session,
                                         TelemetryAt(static_cast<uint64_t>(i), 0.0))
                        .ok());
        (void)registry_.Snapshot();
      }
    });
  }
  for (std::thread& thread : threads) thread.join();
  uint64_t latest = 0;
  const std::vector<RobotRecord> all = registry_.ChangedSince(0, &latest);
  ASSERT_EQ(all.size(), static_cast<size_t>(kRobots));
  for (const RobotRecord& record : all) {
    EXPECT_EQ(record.telemetry_count, static_cast<uint64_t>(kMessages));
    EXPECT_EQ(record.last_telemetry->sequence, static_cast<uint64_t>(kMessages));
  }
  EXPECT_EQ(latest, static_cast<uint64_t>(kRobots + kRobots * kMessages));
}

TEST(FleetRegistryParamsTest, ValidateAcceptsDefaultsAndRejectsZeroNegativeAndNonFinite) {
  EXPECT_TRUE(FleetRegistryParams{}.Validate().ok());
  EXPECT_TRUE(FleetRegistryParams{0.001}.Validate().ok());
  for (double bad : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN(),
                     std::numeric_limits<double>::infinity()}) {
    const absl::Status status = FleetRegistryParams{bad}.Validate();
    EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument) << bad;
    EXPECT_THAT(std::string(status.message()), HasSubstr("stale_after_s"));
  }
}

}  // namespace
}  // namespace fleetnav::server
