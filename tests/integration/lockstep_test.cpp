// The server's side of a simulated run's lockstep (docs/simulator.md, "Lockstep"), with real
// ServerLinks over loopback gRPC: each tick is taken in once every robot of it has ended it,
// and nothing the server sends reaches an agent before the tick that follows it.
#include <grpcpp/create_channel.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <barrier>
#include <chrono>
#include <future>
#include <thread>

#include "fleet_fixture.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/proto/telemetry_convert.hpp"
#include "fleetnav/robot_agent/server_link.hpp"

namespace fleetnav {
namespace {

using testing::FleetServerFixture;

class LockstepTest : public FleetServerFixture {
 protected:
  server::FleetServerParams Params() override {
    server::FleetServerParams params = FleetServerFixture::Params();
    params.dispatch_period_s = 0.05;
    return params;
  }
  std::shared_ptr<grpc::Channel> Channel() {
    return grpc::CreateChannel("127.0.0.1:" + std::to_string(port_),
                               grpc::InsecureChannelCredentials());
  }
  std::unique_ptr<agent::ServerLink> Link(const std::string& robot_id) {
    agent::ServerLinkParams params;
    params.lockstep = true;
    return std::make_unique<agent::ServerLink>(
        Channel(), RobotIdentity{robot_id, LelyVectorModel(), {"straight"}, "test"}, params);
  }
  void WaitOnline(int count) {
    for (int tries = 0; tries < 500; ++tries) {
      grpc::ClientContext context;
      v1::ListRobotsResponse robots;
      if (fleet_->ListRobots(&context, v1::ListRobotsRequest{}, &robots).ok()) {
        int online = 0;
        for (const auto& r : robots.robots()) {
          online += r.connection() == v1::CONNECTION_STATE_ONLINE ? 1 : 0;
        }
        if (online == count) return;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    FAIL() << "robots did not come online";
  }
};

/// A frame of a tick after which the simulation holds: EndTick returns once the server has
/// taken the tick in.
SensorFrame FrameOf(uint64_t tick) {
  SensorFrame frame;
  frame.tick = tick;
  frame.stamp_ns = static_cast<int64_t>(tick) * 20'000'000;
  frame.lockstep_robot_ids = {"r1", "r2"};
  frame.holds_after = true;
  return frame;
}

TEST_F(LockstepTest, EveryTickEndsOnceBothRobotsHaveEndedIt) {
  std::unique_ptr<agent::ServerLink> r1 = Link("r1");
  std::unique_ptr<agent::ServerLink> r2 = Link("r2");
  WaitOnline(2);
  constexpr uint64_t kTicks = 2000;
  std::barrier sim(2);  // the simulator's barrier: both answer a tick before the next
  auto drive = [&](agent::ServerLink* link) {
    for (uint64_t tick = 0; tick < kTicks; ++tick) {
      // As the agent does: the server takes a tick in while the simulator steps, and a frame
      // begins once it has; the server's tick is every 5th and every 100th tick the
      // simulation holds. Telemetry goes on the other ticks.
      SensorFrame frame = FrameOf(tick);
      frame.holds_after = tick % 100 == 99;
      if (tick % 5 != 4 && !frame.holds_after) frame.lockstep_robot_ids.clear();
      link->BeginTick();
      Telemetry telemetry;
      telemetry.stamp_ns = frame.stamp_ns;
      telemetry.sequence = tick + 1;
      if (tick % 5 == 0) link->Publish(telemetry);
      link->EndTick(frame);
      sim.arrive_and_wait();
    }
  };
  auto one = std::async(std::launch::async, drive, r1.get());
  auto two = std::async(std::launch::async, drive, r2.get());
  const bool one_done = one.wait_for(std::chrono::seconds(120)) == std::future_status::ready;
  const bool two_done = two.wait_for(std::chrono::seconds(120)) == std::future_status::ready;
  if (!one_done || !two_done) {  // closing ends the waits, so that the test ends
    r1->Close(0.0);
    r2->Close(0.0);
  }
  EXPECT_TRUE(one_done) << "r1 waits for a tick that never ends";
  EXPECT_TRUE(two_done) << "r2 waits for a tick that never ends";
  // The last tick held: everything sent before it, on whichever tick, has been taken in.
  grpc::ClientContext context;
  v1::ListRobotsResponse robots;
  ASSERT_TRUE(fleet_->ListRobots(&context, v1::ListRobotsRequest{}, &robots).ok());
  ASSERT_EQ(robots.robots_size(), 2);
  for (const v1::RobotState& robot : robots.robots()) {
    EXPECT_EQ(robot.last_telemetry().sequence(), kTicks - 4) << robot.robot_id();
  }
}

// A job submitted while the simulation stands between ticks is dispatched at the next tick and
// reaches the robot with that tick's TickAck — never earlier, however long it stands — so the
// robot starts it at the same tick in every run.
TEST_F(LockstepTest, AJobSubmittedBetweenTicksReachesTheRobotWithTheNextTick) {
  PutBarn();
  ASSERT_TRUE(PutRoute(StraightRoute("short", 1.0)).ok());
  std::unique_ptr<agent::ServerLink> r1 = Link("r1");
  WaitOnline(1);
  auto frame = [](uint64_t tick) {
    SensorFrame f = FrameOf(tick);
    f.lockstep_robot_ids = {"r1"};
    return f;
  };
  Telemetry telemetry;
  telemetry.stamp_ns = 0;
  telemetry.sequence = 1;
  r1->Publish(telemetry);
  r1->EndTick(frame(0));
  v1::SubmitJobResponse submitted;
  ASSERT_TRUE(Submit("short", "between-ticks", &submitted).ok());
  // The dispatcher has no thread of its own in lockstep, and what the server sends waits for
  // the next TickAck: nothing comes while the simulation stands.
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_FALSE(r1->TakeAssignment().has_value());
  // Tick 1 does not hold: EndTick returns at once, the server takes the tick in while the
  // simulator steps, and the next frame begins only once it has (and its assignment is in).
  SensorFrame through = frame(1);
  through.holds_after = false;
  r1->EndTick(through);
  r1->BeginTick();
  std::optional<JobAssignment> assignment = r1->TakeAssignment();
  ASSERT_TRUE(assignment.has_value());
  EXPECT_EQ(assignment->job.job_id, submitted.job().job_id());

  // An operator's cancel is sent at once, between ticks; the link hands it over only with the
  // next TickAck.
  r1->SetCurrentJob(submitted.job().job_id());
  grpc::ClientContext context;
  v1::CancelJobRequest cancel;
  cancel.set_job_id(submitted.job().job_id());
  cancel.set_reason("between ticks");
  v1::CancelJobResponse cancelled;
  ASSERT_TRUE(fleet_->CancelJob(&context, cancel, &cancelled).ok());
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  auto has_cancel = [](const std::vector<JobCommand>& commands) {
    return std::any_of(commands.begin(), commands.end(),
                       [](const JobCommand& c) { return c.type == JobCommandType::kCancel; });
  };
  EXPECT_FALSE(has_cancel(r1->TakeCommands()));
  r1->EndTick(frame(2));
  EXPECT_TRUE(has_cancel(r1->TakeCommands()));
}

// An agent whose stream reaches the server while the simulator waits for its command may have
// answered that tick alone; its hello says from which tick it takes part, and the others' tick
// does not wait for it (before, both agents of a run started under load could wait for ever).
TEST_F(LockstepTest, AStreamThatJoinsMidTickIsNotWaitedForTheTicksItsAgentAnsweredAlone) {
  std::unique_ptr<agent::ServerLink> r1 = Link("r1");
  WaitOnline(1);
  r1->EndTick(FrameOf(0));  // r2 has no stream yet: tick 0 is r1's alone

  std::unique_ptr<v1::AgentService::Stub> agents = v1::AgentService::NewStub(Channel());
  grpc::ClientContext context;
  auto r2 = agents->Connect(&context);
  v1::AgentMessage hello;
  *hello.mutable_hello() = ToProto(RobotIdentity{"r2", LelyVectorModel(), {}, "test"});
  hello.mutable_hello()->set_lockstep(true);
  hello.mutable_hello()->set_lockstep_from_tick(2);  // it answered tick 1 before it was live
  ASSERT_TRUE(r2->Write(hello));
  WaitOnline(2);

  auto tick_one = std::async(std::launch::async, [&] { r1->EndTick(FrameOf(1)); });
  const bool answered = tick_one.wait_for(std::chrono::seconds(30)) == std::future_status::ready;
  if (!answered) r1->Close(0.0);
  EXPECT_TRUE(answered) << "tick 1 waits for r2, which answered it before it joined";

  // From tick 2 on r2 is waited for.
  auto tick_two = std::async(std::launch::async, [&] { r1->EndTick(FrameOf(2)); });
  EXPECT_EQ(tick_two.wait_for(std::chrono::milliseconds(300)), std::future_status::timeout);
  v1::AgentMessage done;
  done.mutable_tick_done()->set_tick(2);
  done.mutable_tick_done()->set_sim_time_ns(FrameOf(2).stamp_ns);
  for (const std::string& id : FrameOf(2).lockstep_robot_ids) {
    done.mutable_tick_done()->add_lockstep_robot_ids(id);
  }
  ASSERT_TRUE(r2->Write(done));
  const bool second = tick_two.wait_for(std::chrono::seconds(30)) == std::future_status::ready;
  if (!second) r1->Close(0.0);
  EXPECT_TRUE(second) << "tick 2 never ended although both robots ended it";
  r2->WritesDone();
  context.TryCancel();
}

}  // namespace
}  // namespace fleetnav
