// fleetnavd's use cases assembled (FleetApp) without a transport: a real SQLite file, a mailbox
// that records what robots are told, and a ManualClock that decides when housekeeping is due.
#include "fleetnav/server/fleet_app.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <tuple>
#include <vector>

#include "fleetnav/core/clock.hpp"
#include "fleetnav/core/robot_model.hpp"

namespace fleetnav::server {
namespace {

using ::testing::ElementsAre;

constexpr int64_t kSecondNs = 1'000'000'000;
constexpr int64_t kUnixMsAtZero = 1'700'000'000'000;

class RecordingMailbox : public RobotMailbox {
 public:
  bool SendAssignment(const std::string&, const JobAssignment&) override { return true; }
  bool SendCommand(const std::string&, const JobCommand&) override { return true; }
  bool SendClearance(const std::string&, const ClearanceNotice&) override { return true; }
  void BroadcastMapUpdate(const std::string& map_id, uint32_t map_version,
                          uint32_t marker_set_version) override {
    updates.emplace_back(map_id, map_version, marker_set_version);
  }
  std::vector<std::tuple<std::string, uint32_t, uint32_t>> updates;
};

class FleetAppTest : public ::testing::Test {
 protected:
  FleetAppParams Params(const std::string& name) {
    FleetAppParams params;
    params.db_path = ::testing::TempDir() + "/fleet_app_" + name + ".db";
    std::filesystem::remove(params.db_path);
    params.pose_history.period_s = 1.0;
    params.registry.stale_after_s = 2.0;
    return params;
  }

  static RobotIdentity Lely(const std::string& robot_id) {
    RobotIdentity identity;
    identity.robot_id = robot_id;
    identity.model = LelyVectorModel();
    identity.capabilities = {"straight"};
    return identity;
  }

  ManualClock clock_{0, kUnixMsAtZero};
  RecordingMailbox mailbox_;
};

TEST_F(FleetAppTest, BadParametersAreRefusedBeforeAStoreIsCreated) {
  FleetAppParams params = Params("bad");
  params.dispatch_period_s = 0.0;
  FleetApp app(params, &clock_, &mailbox_);
  const absl::Status opened = app.Open();
  EXPECT_EQ(opened.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(opened.message(), ::testing::HasSubstr("dispatch_period_s"));
  EXPECT_FALSE(std::filesystem::exists(params.db_path));
}

TEST_F(FleetAppTest, PuttingAMapOrMarkerSetTellsEveryRobotTheLatestVersions) {
  FleetApp app(Params("site"), &clock_, &mailbox_);
  ASSERT_TRUE(app.Open().ok());
  const OccupancyGrid grid = OccupancyGrid::Filled(50, 50, 0.1, Pose2(), 0).value();
  ASSERT_TRUE(app.maps().Put("hall", grid, "").ok());
  MarkerSet markers;
  markers.map_id = "hall";
  StripeMarker marker;
  marker.id = 1;
  marker.position_m = {2.0, 2.0};
  markers.markers.push_back(marker);
  ASSERT_TRUE(app.site().PutMarkerSet(markers).ok());
  // A refused put tells nobody.
  EXPECT_FALSE(app.maps().Put("Bad Id", grid, "").ok());
  EXPECT_THAT(mailbox_.updates,
              ElementsAre(std::make_tuple("hall", 1u, 0u), std::make_tuple("hall", 1u, 1u)));
}

TEST_F(FleetAppTest, HousekeepingIsDueByTheInjectedClockAndStampsWithIt) {
  FleetApp app(Params("house"), &clock_, &mailbox_);
  ASSERT_TRUE(app.Open().ok());
  const uint64_t session = app.sessions().Open(Lely("lely1"), "");
  Telemetry telemetry;
  telemetry.pose_in_map = Pose2(3.0, 4.0, 0.0);
  ASSERT_TRUE(app.sessions().RecordTelemetry("lely1", session, telemetry).ok());

  app.KeepHouse(clock_.NowNs());  // schedules the first sample one period on
  clock_.AdvanceNs(kSecondNs / 2);
  app.KeepHouse(clock_.NowNs());
  EXPECT_TRUE(app.pose_history().ListPoses("lely1", 0, 10)->empty());
  clock_.AdvanceNs(kSecondNs / 2);
  app.KeepHouse(clock_.NowNs());
  const absl::StatusOr<std::vector<storage::PoseSample>> samples =
      app.pose_history().ListPoses("lely1", 0, 10);
  ASSERT_TRUE(samples.ok());
  ASSERT_EQ(samples->size(), 1u);
  EXPECT_EQ((*samples)[0].unix_ms, kUnixMsAtZero + 1000);  // the clock's calendar, not the wall's
  EXPECT_NEAR((*samples)[0].pose_in_map.x_m(), 3.0, 1e-9);

  // No telemetry for longer than stale_after_s: shown stale at the next housekeeping.
  EXPECT_EQ(app.registry().Get("lely1")->connection, ConnectionState::kOnline);
  clock_.AdvanceNs(3 * kSecondNs);
  app.KeepHouse(clock_.NowNs());
  EXPECT_EQ(app.registry().Get("lely1")->connection, ConnectionState::kStale);
}

TEST_F(FleetAppTest, AccessControlExistsOnlyWhenAuthorizingAndTakesTheFilesTokens) {
  FleetApp open_app(Params("open"), &clock_, &mailbox_);
  ASSERT_TRUE(open_app.Open().ok());
  EXPECT_EQ(open_app.access(), nullptr);

  FleetAppParams params = Params("secure");
  params.authorize = true;
  params.file_tokens = {{"ada", Role::kAdmin, Sha256Hex("ada-secret")}};
  FleetApp app(params, &clock_, &mailbox_);
  ASSERT_TRUE(app.Open().ok());
  ASSERT_NE(app.access(), nullptr);
  EXPECT_TRUE(app.access()->AuthorizeHttp(true, "Bearer ada-secret").ok());
  EXPECT_EQ(app.access()->AuthorizeHttp(false, "Bearer wrong").status().code(),
            absl::StatusCode::kUnauthenticated);
  EXPECT_EQ(app.access()->counts().admitted, 1u);
  EXPECT_EQ(app.access()->counts().unauthenticated, 1u);
}

}  // namespace
}  // namespace fleetnav::server
