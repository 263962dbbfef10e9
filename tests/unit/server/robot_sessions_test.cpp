// The rules of a robot's session (RobotSessions) without a transport: in-memory repositories, a
// mailbox that records what robots are told and a ManualClock.
#include "fleetnav/server/robot_sessions.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "fleetnav/core/clock.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "memory_site.hpp"

namespace fleetnav::server {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;

constexpr int64_t kSecondNs = 1'000'000'000;

class RecordingMailbox : public RobotMailbox {
 public:
  bool SendAssignment(const std::string& robot_id, const JobAssignment&) override {
    ++assignments[robot_id];
    return true;
  }
  bool SendCommand(const std::string&, const JobCommand&) override { return true; }
  bool SendClearance(const std::string&, const ClearanceNotice&) override { return true; }
  void BroadcastMapUpdate(const std::string& map_id, uint32_t map_version,
                          uint32_t marker_set_version) override {
    updates.emplace_back(map_id, map_version, marker_set_version);
  }

  std::map<std::string, int> assignments;
  std::vector<std::tuple<std::string, uint32_t, uint32_t>> updates;
};

class RobotSessionsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(memory_.hall_ok);
    Route alley;
    alley.name = "alley";
    alley.map_id = "hall";
    alley.actions.push_back(RouteAction{StraightAction{3.0, 0.25}, {}});
    ASSERT_TRUE(memory_.catalog.PutRoute(alley).ok());
    JobServiceParams params;
    params.lost_robot_timeout_s = 30.0;
    jobs_ = std::make_unique<JobService>(&memory_.jobs, &memory_.robots, &memory_.cache,
                                         &memory_.catalog, &registry_, &mailbox_, &clock_, params);
    ASSERT_TRUE(jobs_->Recover().ok());
    InputLimits limits;
    limits.max_capabilities = 4;
    sessions_ = std::make_unique<RobotSessions>(&registry_, jobs_.get(), &mailbox_, &maps_,
                                                &memory_.catalog, limits);
  }

  static RobotIdentity Lely(const std::string& robot_id) {
    RobotIdentity identity;
    identity.robot_id = robot_id;
    identity.model = LelyVectorModel();
    identity.capabilities = {"straight", "turn"};
    return identity;
  }

  static Telemetry At(double x_m) {
    Telemetry telemetry;
    telemetry.pose_in_map = Pose2(x_m, 1.0, 0.0);
    return telemetry;
  }

  std::string SubmitAlley() {
    SubmitJobRequest request;
    request.route_name = "alley";
    absl::StatusOr<storage::CreatedJob> created = jobs_->Submit(request);
    EXPECT_TRUE(created.ok()) << created.status();
    return created.ok() ? created->job.job_id : "";
  }

  ManualClock clock_{0, 1'700'000'000'000};
  testing::MemorySite memory_{&clock_};
  MapCatalog maps_{&memory_.cache, &clock_};
  FleetRegistry registry_{&clock_, FleetRegistryParams{}};
  RecordingMailbox mailbox_;
  std::unique_ptr<JobService> jobs_;
  std::unique_ptr<RobotSessions> sessions_;
};

TEST_F(RobotSessionsTest, AHelloBeyondTheLimitsIsRefusedAndNothingOfItIsKept) {
  RobotIdentity greedy = Lely("greedy");
  greedy.capabilities = {"a", "b", "c", "d", "e"};
  const absl::Status refused = sessions_->CheckHello(greedy);
  EXPECT_EQ(refused.code(), absl::StatusCode::kResourceExhausted);
  EXPECT_THAT(refused.message(), HasSubstr("max_capabilities"));
  EXPECT_TRUE(registry_.Snapshot().empty());
  EXPECT_TRUE(sessions_->CheckHello(Lely("lely1")).ok());
}

TEST_F(RobotSessionsTest, OpeningRegistersTheRobotOnlineAndItsTelemetryCounts) {
  const uint64_t session = sessions_->Open(Lely("lely1"), "");
  ASSERT_TRUE(registry_.Get("lely1").ok());
  EXPECT_EQ(registry_.Get("lely1")->connection, ConnectionState::kOnline);
  ASSERT_TRUE(sessions_->RecordTelemetry("lely1", session, At(2.0)).ok());
  EXPECT_EQ(registry_.Get("lely1")->telemetry_count, 1u);
  EXPECT_NEAR(registry_.Get("lely1")->last_telemetry->pose_in_map.x_m(), 2.0, 1e-12);
  // A queued job goes to the robot at the next dispatch pass.
  SubmitAlley();
  jobs_->DispatchOnce();
  EXPECT_EQ(mailbox_.assignments["lely1"], 1);
}

TEST_F(RobotSessionsTest, AReplacedSessionCanNeitherReportNorEndTheNewOne) {
  const uint64_t first = sessions_->Open(Lely("lely1"), "");
  const std::string job_id = SubmitAlley();
  jobs_->DispatchOnce();
  ASSERT_EQ(jobs_->Get(job_id)->state, JobState::kAssigned);
  const uint64_t second = sessions_->Open(Lely("lely1"), job_id);  // reconnects, resumes the job
  ASSERT_NE(first, second);

  EXPECT_EQ(sessions_->RecordTelemetry("lely1", first, At(3.0)).code(),
            absl::StatusCode::kFailedPrecondition);
  JobEvent failed;
  failed.job_id = job_id;
  failed.state = JobState::kFailed;
  EXPECT_EQ(sessions_->RecordJobEvent("lely1", first, failed).code(),
            absl::StatusCode::kFailedPrecondition);
  EXPECT_EQ(sessions_->CheckSession("lely1", first).code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_NE(jobs_->Get(job_id)->state, JobState::kFailed);

  // The old stream closing leaves the robot online on its new one.
  sessions_->Close("lely1", first);
  EXPECT_EQ(registry_.Get("lely1")->connection, ConnectionState::kOnline);
  EXPECT_TRUE(sessions_->RecordTelemetry("lely1", second, At(3.0)).ok());

  // The new one closing takes it offline; its job is paused to wait for it.
  sessions_->Close("lely1", second);
  EXPECT_EQ(registry_.Get("lely1")->connection, ConnectionState::kOffline);
  EXPECT_EQ(jobs_->Get(job_id)->state, JobState::kPaused);
}

TEST_F(RobotSessionsTest, ARobotLostLongerThanTheTimeoutLosesItsJobByTheInjectedClock) {
  const uint64_t session = sessions_->Open(Lely("lely1"), "");
  const std::string job_id = SubmitAlley();
  jobs_->DispatchOnce();
  sessions_->Close("lely1", session);
  clock_.AdvanceNs(29 * kSecondNs);
  jobs_->DispatchOnce();
  EXPECT_EQ(jobs_->Get(job_id)->state, JobState::kPaused);
  clock_.AdvanceNs(2 * kSecondNs);
  jobs_->DispatchOnce();
  EXPECT_EQ(jobs_->Get(job_id)->state, JobState::kFailed);  // on_robot_lost: fail (default)
}

TEST_F(RobotSessionsTest, RobotsAreToldTheLatestMapAndMarkerSetVersions) {
  MarkerSet markers;
  markers.map_id = "hall";
  StripeMarker marker;
  marker.id = 1;
  marker.position_m = {2.0, 2.0};
  markers.markers.push_back(marker);
  ASSERT_TRUE(memory_.catalog.PutMarkerSet(markers).ok());
  sessions_->AnnounceSite("hall");
  EXPECT_THAT(mailbox_.updates, ElementsAre(std::make_tuple("hall", 1u, 1u)));
}

}  // namespace
}  // namespace fleetnav::server
