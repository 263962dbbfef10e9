// SiteCatalog's versioning of marker sets and routes.
#include "fleetnav/server/site/site_catalog.hpp"

#include <gtest/gtest.h>

#include "fleetnav/core/clock.hpp"
#include "memory_site.hpp"

namespace fleetnav::server {
namespace {

class SiteCatalogTest : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_TRUE(memory_.hall_ok); }

  static Route Alley(double distance_m) {
    Route route;
    route.name = "alley";
    route.map_id = "hall";
    route.actions.push_back(RouteAction{StraightAction{distance_m, 0.25}, {}});
    return route;
  }
  static MarkerSet Markers(double x_m) {
    MarkerSet markers;
    markers.map_id = "hall";
    StripeMarker marker;
    marker.id = 1;
    marker.position_m = Eigen::Vector2d(x_m, 2.0);
    markers.markers.push_back(marker);
    return markers;
  }

  ManualClock clock_;
  testing::MemorySite memory_{&clock_};
  SiteCatalog& site_ = memory_.catalog;
};

TEST_F(SiteCatalogTest, TheSameRouteAgainIsTheVersionThatHoldsIt) {
  EXPECT_EQ(site_.PutRoute(Alley(3.0)).value(), 1u);
  EXPECT_EQ(site_.PutRoute(Alley(3.0)).value(), 1u);
  EXPECT_EQ(site_.PutRoute(Alley(3.5)).value(), 2u);
  EXPECT_EQ(site_.PutRoute(Alley(3.0)).value(), 3u);  // only the latest is compared
  EXPECT_EQ(site_.ListRoutes("hall").value().size(), 1u);
}

TEST_F(SiteCatalogTest, TheSameMarkerSetAgainIsTheVersionThatHoldsIt) {
  EXPECT_EQ(site_.PutMarkerSet(Markers(1.0)).value(), 1u);
  EXPECT_EQ(site_.PutMarkerSet(Markers(1.0)).value(), 1u);
  EXPECT_EQ(site_.PutMarkerSet(Markers(1.5)).value(), 2u);
  EXPECT_EQ(site_.LatestMarkerSetVersion("hall"), 2u);
}

TEST_F(SiteCatalogTest, ARouteIsDeletedOnlyWhenNoUnfinishedJobRunsIt) {
  ASSERT_TRUE(site_.PutRoute(Alley(3.0)).ok());
  Job job;
  job.route_name = "alley";
  job.route_version = 1;
  job.map_id = "hall";
  job.state = JobState::kRunning;
  JobEvent queued;
  queued.type = JobEventType::kQueued;
  const std::string job_id = memory_.jobs.CreateJob(job, queued).value().job.job_id;
  const absl::Status refused = site_.DeleteRoute("alley");
  EXPECT_EQ(refused.code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_NE(refused.message().find(job_id), std::string::npos) << refused;
  // The map cannot go while the route is there.
  EXPECT_EQ(site_.DeleteMap("hall").code(), absl::StatusCode::kFailedPrecondition);

  job = memory_.jobs.GetJob(job_id).value();
  job.state = JobState::kSucceeded;
  ASSERT_TRUE(memory_.jobs.UpdateJob(job, queued).ok());
  EXPECT_TRUE(site_.DeleteRoute("alley").ok());
  EXPECT_EQ(site_.GetRoute("alley", 0).status().code(), absl::StatusCode::kNotFound);
  EXPECT_EQ(site_.DeleteRoute("alley").code(), absl::StatusCode::kNotFound);
  EXPECT_EQ(site_.DeleteRoute("no/such").code(), absl::StatusCode::kInvalidArgument);
  EXPECT_TRUE(site_.DeleteMap("hall").ok());
}

TEST_F(SiteCatalogTest, MarkersAreDeletedOnlyWhenNoRouteNeedsThem) {
  ASSERT_TRUE(site_.PutMarkerSet(Markers(1.0)).ok());
  Route to_marker = Alley(3.0);
  to_marker.name = "to-marker";
  to_marker.actions[0].end = EndCondition{EndConditionKind::kMarkerDetected, 1};
  ASSERT_TRUE(site_.PutRoute(to_marker).ok());
  ASSERT_TRUE(site_.PutRoute(Alley(3.0)).ok());  // needs no marker
  const absl::Status refused = site_.DeleteMarkerSet("hall");
  EXPECT_EQ(refused.code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_NE(refused.message().find("to-marker"), std::string::npos) << refused;
  ASSERT_TRUE(site_.DeleteRoute("to-marker").ok());
  EXPECT_TRUE(site_.DeleteMarkerSet("hall").ok());
  EXPECT_EQ(site_.LatestMarkerSetVersion("hall"), 0u);
  EXPECT_EQ(site_.DeleteMarkerSet("hall").code(), absl::StatusCode::kNotFound);
  EXPECT_EQ(site_.DeleteMarkerSet("Hall!").code(), absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace fleetnav::server
