// fleetnavctl's commands against a real fleetnavd over loopback: what an operator types, what
// the tables and JSON say, and the errors for bad files.
#include <gmock/gmock.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "fleet_fixture.hpp"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/map_io.hpp"
#include "fleetnav/ctl/commands.hpp"

namespace fleetnav {
namespace {

using ::testing::HasSubstr;

class FleetnavctlTest : public testing::FleetServerFixture {
 protected:
  ctl::CommandContext Context(bool json = false) {
    return ctl::CommandContext{channel_, &out_, json, 5.0};
  }
  std::string Take() {
    std::string text = out_.str();
    out_.str("");
    return text;
  }
  std::string WriteFile(const std::string& name, const std::string& text) {
    const std::string path = testing::UniqueTempPath(name);
    std::ofstream(path) << text;
    return path;
  }
  std::ostringstream out_;
};

TEST_F(FleetnavctlTest, ImportsAMapStoresARouteAndSubmitsAJob) {
  absl::StatusOr<OccupancyGrid> grid = OccupancyGrid::Filled(40, 30, 0.1, Pose2(), 0);
  const std::string yaml_path = testing::UniqueTempPath("ctl-map") + ".yaml";
  ASSERT_TRUE(SaveMapServer(*grid, yaml_path).ok());
  ASSERT_TRUE(ctl::ImportMap(Context(), "barn", yaml_path, "test barn").ok());
  EXPECT_THAT(Take(), HasSubstr("imported map 'barn' as version 1"));
  ASSERT_TRUE(ctl::ListMaps(Context(/*json=*/true)).ok());
  const nlohmann::json maps = nlohmann::json::parse(Take());
  ASSERT_EQ(maps.size(), 1u);
  EXPECT_EQ(maps[0]["width"], 40);
  EXPECT_EQ(maps[0]["description"], "test barn");

  const std::string route = WriteFile("route.yaml",
                                      "name: alley\nmap: barn\nactions:\n"
                                      "  - straight: {distance: 1.0}\n");
  ASSERT_TRUE(ctl::PutRoute(Context(), route).ok());
  EXPECT_THAT(Take(), HasSubstr("stored route 'alley' (1 actions) as version 1"));

  ctl::SubmitOptions submit;
  submit.route_name = "alley";
  submit.idempotency_key = "order-1";
  absl::StatusOr<std::string> id = ctl::SubmitJob(Context(), submit);
  ASSERT_TRUE(id.ok()) << id.status();
  EXPECT_EQ(*id, "job-000001");
  EXPECT_EQ(*ctl::SubmitJob(Context(), submit), "job-000001");  // same key, same job
  Take();
  // A go-to-goal on the map (job submit --goal X Y YAW_DEG --map ID).
  ctl::SubmitOptions go;
  go.goal = {1.0, 0.5, 90.0};
  go.goal_map_id = "barn";
  absl::StatusOr<std::string> goal_id = ctl::SubmitJob(Context(), go);
  ASSERT_TRUE(goal_id.ok()) << goal_id.status();
  {
    grpc::ClientContext rpc;
    v1::GetJobRequest request;
    request.set_job_id(*goal_id);
    v1::GetJobResponse response;
    ASSERT_TRUE(fleet_->GetJob(&rpc, request, &response).ok());
    EXPECT_EQ(response.job().goal().map_id(), "barn");
    EXPECT_NEAR(response.job().goal().goal().x_m(), 1.0, 1e-9);
    EXPECT_NEAR(response.job().goal().goal().yaw_rad(), kPi / 2, 1e-9);
  }
  go.goal_map_id = "nowhere";
  EXPECT_EQ(ctl::SubmitJob(Context(), go).status().code(), absl::StatusCode::kNotFound);
  Take();
  ASSERT_TRUE(ctl::ListJobs(Context(), "queued", "", 10).ok());
  const std::string table = Take();
  EXPECT_THAT(table, HasSubstr("JOB"));
  EXPECT_THAT(table, HasSubstr("job-000001  queued"));
  ASSERT_TRUE(ctl::CancelJob(Context(), "job-000001", "test").ok());
  Take();
  // Watching an ended job replays it and reports the cancellation as an error for scripts.
  const absl::Status watched = ctl::WatchJob(Context(), "job-000001");
  EXPECT_EQ(watched.code(), absl::StatusCode::kAborted);
  EXPECT_THAT(Take(), HasSubstr("cancelled"));
}

TEST_F(FleetnavctlTest, BadFilesAndUnknownThingsAreClearErrors) {
  EXPECT_EQ(ctl::ImportMap(Context(), "barn", "/nonexistent/map.yaml", "").code(),
            absl::StatusCode::kNotFound);
  const std::string bad_route =
      WriteFile("bad-route.yaml", "name: r\nmap: barn\nactions:\n  - jump: {height: 2}\n");
  const absl::Status route = ctl::PutRoute(Context(), bad_route);
  EXPECT_EQ(route.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(route.message(), HasSubstr("jump"));
  EXPECT_EQ(ctl::GetJob(Context(), "job-424242").code(), absl::StatusCode::kNotFound);
  EXPECT_EQ(ctl::ListJobs(Context(), "sleeping", "", 10).code(),
            absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace fleetnav
