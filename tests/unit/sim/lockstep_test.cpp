#include "fleetnav/sim/lockstep.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <functional>
#include <map>
#include <thread>
#include <vector>

#include "absl/synchronization/notification.h"
#include "absl/time/clock.h"
#include "absl/time/time.h"
#include "sim_test_util.hpp"

namespace fleetnav::sim {
namespace {

using testing::MakeSimulation;
using testing::TwistCommand;

// Polls until `done` holds; false after a generous deadline (a hang guard, not a timing check).
bool EventuallyTrue(const std::function<bool()>& done) {
  const absl::Time deadline = absl::Now() + absl::Seconds(20);
  while (!done()) {
    if (absl::Now() > deadline) return false;
    absl::SleepFor(absl::Milliseconds(1));
  }
  return true;
}

ActuatorCommand Answer(const SensorFrame& frame, double vx_mps = 0.0) {
  ActuatorCommand command = TwistCommand(vx_mps, 0.0);
  command.tick = frame.tick;
  return command;
}

// A simulation with two robots and a lockstep loop running on its own thread; the loop is
// always stopped and joined on destruction.
class LockstepTest : public ::testing::Test {
 protected:
  void StartLoop(LockstepParams params) {
    sim_ = MakeSimulation(4);
    ASSERT_TRUE(sim_->AddRobot("a", "lely-vector", Pose2(0, 0, 0)).ok());
    ASSERT_TRUE(sim_->AddRobot("b", "lely-vector", Pose2(0, 10, 0)).ok());
    ASSERT_TRUE(params.Validate().ok());
    lockstep_ = std::make_unique<Lockstep>(sim_.get(), params);
  }
  void RunLoop() {
    loop_ = std::thread([this] { lockstep_->Run(); });
  }
  void TearDown() override {
    if (lockstep_) lockstep_->Stop();
    if (loop_.joinable()) loop_.join();
  }

  std::unique_ptr<Simulation> sim_;
  std::unique_ptr<Lockstep> lockstep_;
  std::thread loop_;
};

// Each agent on its own thread; agent b holds back its answer for tick 0. Agent a has answered
// tick 0 and waits, and the tick stays at 0 until b answers too.
TEST_F(LockstepTest, TickWaitsForEveryAttachedAgent) {
  StartLoop(LockstepParams{.min_attached = 2});
  absl::StatusOr<std::unique_ptr<Attachment>> a = lockstep_->Attach("a");
  absl::StatusOr<std::unique_ptr<Attachment>> b = lockstep_->Attach("b");
  ASSERT_TRUE(a.ok() && b.ok());
  RunLoop();

  constexpr int kTicks = 30;
  std::atomic<int> a_answered{0};
  std::atomic<int> a_frames{0};
  absl::Notification b_has_frame0, release_b;
  std::vector<uint64_t> a_ticks, b_ticks;
  std::vector<int64_t> a_stamps;
  std::thread agent_a([&] {
    for (int i = 0; i < kTicks; ++i) {
      std::optional<SensorFrame> frame = (*a)->WaitFrame();
      if (!frame) return;
      ++a_frames;
      a_ticks.push_back(frame->tick);
      a_stamps.push_back(frame->stamp_ns);
      EXPECT_TRUE((*a)->Submit(Answer(*frame, 0.2)).ok());
      ++a_answered;
    }
  });
  std::thread agent_b([&] {
    for (int i = 0; i < kTicks; ++i) {
      std::optional<SensorFrame> frame = (*b)->WaitFrame();
      if (!frame) return;
      b_ticks.push_back(frame->tick);
      if (i == 0) {
        b_has_frame0.Notify();
        release_b.WaitForNotification();
      }
      EXPECT_TRUE((*b)->Submit(Answer(*frame)).ok());
    }
  });

  b_has_frame0.WaitForNotification();
  EXPECT_TRUE(EventuallyTrue([&] { return a_answered.load() == 1; }));
  // Give the loop every chance to advance wrongly.
  absl::SleepFor(absl::Milliseconds(100));
  EXPECT_EQ(lockstep_->tick(), 0u);
  EXPECT_EQ(a_frames.load(), 1);  // a still waits for the frame of tick 1
  release_b.Notify();

  agent_a.join();
  agent_b.join();
  // Both answered kTicks frames, so the loop advanced kTicks times and waits for tick kTicks.
  EXPECT_TRUE(EventuallyTrue([&] { return lockstep_->tick() == kTicks; }));
  absl::SleepFor(absl::Milliseconds(20));
  EXPECT_EQ(lockstep_->tick(), static_cast<uint64_t>(kTicks));
  ASSERT_EQ(a_ticks.size(), static_cast<size_t>(kTicks));
  ASSERT_EQ(b_ticks.size(), static_cast<size_t>(kTicks));
  for (int i = 0; i < kTicks; ++i) {
    EXPECT_EQ(a_ticks[i], static_cast<uint64_t>(i));
    EXPECT_EQ(b_ticks[i], static_cast<uint64_t>(i));
    EXPECT_EQ(a_stamps[i], static_cast<int64_t>(i) * 20'000'000);
  }
  // a's command moved its robot; b stood still.
  const GroundTruthSnapshot truth = lockstep_->GroundTruth();
  EXPECT_GT(truth.robots.at(0).pose.x_m(), 0.02);
  EXPECT_LT(std::abs(truth.robots.at(1).pose.x_m()), 0.01);
}

TEST_F(LockstepTest, SubmitForAnotherTickIsInvalid) {
  StartLoop(LockstepParams{.min_attached = 1});
  absl::StatusOr<std::unique_ptr<Attachment>> a = lockstep_->Attach("a");
  ASSERT_TRUE(a.ok());
  RunLoop();
  std::optional<SensorFrame> frame = (*a)->WaitFrame();
  ASSERT_TRUE(frame.has_value());
  EXPECT_EQ(frame->tick, 0u);
  ActuatorCommand wrong = Answer(*frame);
  wrong.tick = 5;
  EXPECT_EQ((*a)->Submit(wrong).code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(lockstep_->tick(), 0u);  // a wrong tick does not answer
  EXPECT_TRUE((*a)->Submit(Answer(*frame)).ok());
  // A second answer for the same tick is refused (it may already be the next tick's frame).
  EXPECT_EQ((*a)->Submit(Answer(*frame)).code(), absl::StatusCode::kInvalidArgument);
  std::optional<SensorFrame> next = (*a)->WaitFrame();
  ASSERT_TRUE(next.has_value());
  EXPECT_EQ(next->tick, 1u);
  EXPECT_EQ((*a)->Submit(Answer(*frame)).code(), absl::StatusCode::kInvalidArgument);
  EXPECT_TRUE((*a)->Submit(Answer(*next)).ok());
}

TEST_F(LockstepTest, SecondAttachForARobotFails) {
  StartLoop(LockstepParams{.min_attached = 1});
  absl::StatusOr<std::unique_ptr<Attachment>> a = lockstep_->Attach("a");
  ASSERT_TRUE(a.ok());
  EXPECT_EQ(lockstep_->Attach("a").status().code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_EQ(lockstep_->Attach("nobody").status().code(), absl::StatusCode::kNotFound);
  EXPECT_EQ(lockstep_->attached_count(), 1u);
  // Once detached, the robot can be attached again.
  a->reset();
  EXPECT_EQ(lockstep_->attached_count(), 0u);
  EXPECT_TRUE(lockstep_->Attach("a").ok());
}

// Agent b drives its robot, then goes away in the middle of a tick; the loop carries on with a
// alone and b's robot is stopped.
TEST_F(LockstepTest, LoopContinuesAfterAnAttachmentIsDestroyed) {
  StartLoop(LockstepParams{.min_attached = 1});
  absl::StatusOr<std::unique_ptr<Attachment>> a = lockstep_->Attach("a");
  absl::StatusOr<std::unique_ptr<Attachment>> b = lockstep_->Attach("b");
  ASSERT_TRUE(a.ok() && b.ok());
  RunLoop();
  for (int i = 0; i < 150; ++i) {  // 3 s at 0.4 m/s for b
    std::optional<SensorFrame> fa = (*a)->WaitFrame();
    std::optional<SensorFrame> fb = (*b)->WaitFrame();
    ASSERT_TRUE(fa && fb);
    ASSERT_EQ(fa->tick, fb->tick);
    ASSERT_TRUE((*a)->Submit(Answer(*fa)).ok());
    ASSERT_TRUE((*b)->Submit(Answer(*fb, 0.4)).ok());
  }
  std::optional<SensorFrame> fb = (*b)->WaitFrame();  // b takes tick 150 and never answers
  ASSERT_TRUE(fb);
  b->reset();
  EXPECT_EQ(lockstep_->attached_count(), 1u);
  const double b_speed_before = lockstep_->GroundTruth().robots.at(1).velocity.vx_mps;
  EXPECT_GT(b_speed_before, 0.3);
  uint64_t last_tick = 0;
  for (int i = 0; i < 200; ++i) {
    std::optional<SensorFrame> fa = (*a)->WaitFrame();
    ASSERT_TRUE(fa);
    last_tick = fa->tick;
    ASSERT_TRUE((*a)->Submit(Answer(*fa)).ok());
  }
  EXPECT_EQ(last_tick, 349u);
  EXPECT_TRUE(EventuallyTrue([&] { return lockstep_->tick() >= 350; }));
  // Without an agent b's robot was commanded to stop.
  EXPECT_LT(std::abs(lockstep_->GroundTruth().robots.at(1).velocity.vx_mps), 0.01);
}

TEST_F(LockstepTest, StopEndsWaitFrame) {
  StartLoop(LockstepParams{.min_attached = 2});  // one agent: the loop never ticks
  absl::StatusOr<std::unique_ptr<Attachment>> a = lockstep_->Attach("a");
  ASSERT_TRUE(a.ok());
  RunLoop();
  absl::Notification waiting;
  std::optional<SensorFrame> result = SensorFrame{};
  std::thread agent([&] {
    waiting.Notify();
    result = (*a)->WaitFrame();
  });
  waiting.WaitForNotification();
  absl::SleepFor(absl::Milliseconds(20));
  EXPECT_EQ(lockstep_->tick(), 0u);
  lockstep_->Stop();
  agent.join();
  EXPECT_FALSE(result.has_value());
  EXPECT_TRUE(lockstep_->stopped());
  EXPECT_FALSE((*a)->WaitFrame().has_value());  // and at once afterwards
  loop_.join();
}

TEST_F(LockstepTest, RequestedTicksRunWithoutAgents) {
  StartLoop(LockstepParams{.min_attached = 1});
  RunLoop();
  lockstep_->RequestTicks(10);
  EXPECT_TRUE(EventuallyTrue([&] { return lockstep_->tick() == 10; }));
  absl::SleepFor(absl::Milliseconds(20));
  EXPECT_EQ(lockstep_->tick(), 10u);
  EXPECT_EQ(lockstep_->now_ns(), 200'000'000);
}

TEST_F(LockstepTest, MaxSimTimeStopsTheLoop) {
  StartLoop(LockstepParams{.min_attached = 1, .max_sim_time_s = 0.5});
  absl::StatusOr<std::unique_ptr<Attachment>> a = lockstep_->Attach("a");
  ASSERT_TRUE(a.ok());
  RunLoop();
  int frames = 0;
  while (std::optional<SensorFrame> frame = (*a)->WaitFrame()) {
    ++frames;
    ASSERT_TRUE((*a)->Submit(Answer(*frame)).ok());
    ASSERT_LT(frames, 1000);
  }
  loop_.join();
  EXPECT_EQ(frames, 25);
  EXPECT_EQ(lockstep_->tick(), 25u);
  EXPECT_TRUE(lockstep_->stopped());
}

TEST(LockstepParamsTest, Validate) {
  EXPECT_TRUE(LockstepParams{}.Validate().ok());
  EXPECT_EQ(LockstepParams{.real_time_factor = -1}.Validate().code(),
            absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(LockstepParams{.min_attached = -1}.Validate().code(),
            absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(LockstepParams{.max_sim_time_s = -0.1}.Validate().code(),
            absl::StatusCode::kInvalidArgument);
  const absl::Status no_server_tick = LockstepParams{.server_tick_every = 0}.Validate();
  EXPECT_EQ(no_server_tick.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(no_server_tick.message().find("server_tick_every"), std::string::npos);
}

// A reset while an agent holds a frame: the agent's late answer to the old frame is ignored,
// it gets the frame of tick 0 next, and the run goes on from there.
TEST_F(LockstepTest, ResetReissuesTickZeroAndIgnoresTheStaleAnswer) {
  LockstepParams params;
  params.min_attached = 1;
  StartLoop(params);
  absl::StatusOr<std::unique_ptr<Attachment>> a = lockstep_->Attach("a");
  ASSERT_TRUE(a.ok());
  RunLoop();
  for (int i = 0; i < 10; ++i) {
    std::optional<SensorFrame> frame = (*a)->WaitFrame();
    ASSERT_TRUE(frame.has_value());
    ASSERT_TRUE((*a)->Submit(Answer(*frame, 0.3)).ok());
  }
  std::optional<SensorFrame> held = (*a)->WaitFrame();
  ASSERT_TRUE(held.has_value());
  EXPECT_EQ(held->tick, 10u);
  lockstep_->Reset(5);
  EXPECT_TRUE((*a)->Submit(Answer(*held, 0.3)).ok());  // ignored
  std::optional<SensorFrame> fresh = (*a)->WaitFrame();
  ASSERT_TRUE(fresh.has_value());
  EXPECT_EQ(fresh->tick, 0u);
  ASSERT_TRUE((*a)->Submit(Answer(*fresh, 0.3)).ok());
  std::optional<SensorFrame> next = (*a)->WaitFrame();
  ASSERT_TRUE(next.has_value());
  EXPECT_EQ(next->tick, 1u);
  ASSERT_TRUE((*a)->Submit(Answer(*next, 0.0)).ok());
  lockstep_->Inspect([](const Simulation& sim) {
    EXPECT_LT(sim.GroundTruth().robots[0].pose.x_m(), 0.01);  // back at the start
  });
}

TEST(PhysicalMeetsKinematicTest, LelyDrivingIntoAParkedPlatformIsStoppedAndReported) {
  SimulationParams kinematic;
  kinematic.kinematic_omni = true;
  std::unique_ptr<Simulation> sim = MakeSimulation(6, kinematic);
  ASSERT_TRUE(sim->AddRobot("lely", "lely-vector", Pose2(0, 0, 0)).ok());
  ASSERT_TRUE(sim->AddRobot("omni", "mecanum-platform", Pose2(3.0, 0, 0)).ok());
  ASSERT_TRUE(sim->Command("lely", TwistCommand(0.3, 0.0)).ok());
  for (int i = 0; i < 500; ++i) sim->Advance();
  const GroundTruthSnapshot truth = sim->GroundTruth();
  // The platform does not move; the Lely's front (x + 1.395) stops at its rear (3 - 0.394).
  EXPECT_DOUBLE_EQ(truth.robots[1].pose.x_m(), 3.0);
  EXPECT_LT(truth.robots[0].pose.x_m() + 1.395, 3.0 - 0.394 + 0.02);
  EXPECT_GT(truth.robots[0].up_z, 0.95);
  bool reported = false;
  for (const SimContact& contact : truth.contacts) {
    reported |= contact.robot_id == "lely" && contact.other == "omni";
  }
  EXPECT_TRUE(reported);
  EXPECT_TRUE(sim->Sense("lely")->bumper);
}

TEST(PhysicalMeetsKinematicTest, LelyDrivingIntoAPhysicalPlatformPushesItAndIsReported) {
  std::unique_ptr<Simulation> sim = MakeSimulation(6);
  ASSERT_TRUE(sim->AddRobot("lely", "lely-vector", Pose2(0, 0, 0)).ok());
  ASSERT_TRUE(sim->AddRobot("omni", "mecanum-platform", Pose2(3.0, 0, 0)).ok());
  ASSERT_TRUE(sim->Command("lely", TwistCommand(0.3, 0.0)).ok());
  for (int i = 0; i < 500; ++i) sim->Advance();
  const GroundTruthSnapshot truth = sim->GroundTruth();
  // 1485 kg against 60 kg standing on its wheels' grip: the platform is shoved along.
  EXPECT_GT(truth.robots[1].pose.x_m(), 3.5);
  EXPECT_GT(truth.robots[0].up_z, 0.95);
  EXPECT_GT(truth.robots[1].up_z, 0.9);
  bool reported = false;
  for (const SimContact& contact : truth.contacts) {
    reported |= contact.robot_id == "lely" && contact.other == "omni";
  }
  EXPECT_TRUE(reported);
}

// Held from the start: no tick passes without RunUntil, which stops exactly at the first tick
// at or after the time asked for; every frame names the robots of its tick's barrier.
TEST_F(LockstepTest, AHeldLoopAdvancesOnlyAsFarAsRunUntilAsks) {
  StartLoop(LockstepParams{.min_attached = 1, .start_held = true});
  absl::StatusOr<std::unique_ptr<Attachment>> a = lockstep_->Attach("a");
  absl::StatusOr<std::unique_ptr<Attachment>> b = lockstep_->Attach("b");
  ASSERT_TRUE(a.ok() && b.ok());
  RunLoop();
  std::map<uint64_t, std::vector<std::string>> a_names;  // by tick
  std::vector<uint64_t> a_holds_after;  // the ticks whose frames said the loop holds after them
  std::atomic<bool> stop{false};
  auto answer = [&](Attachment* attachment, bool record) {
    while (!stop.load()) {
      std::optional<SensorFrame> frame = attachment->WaitFrame();
      if (!frame) return;
      if (record) {
        a_names[frame->tick] = frame->lockstep_robot_ids;
        if (frame->holds_after) a_holds_after.push_back(frame->tick);
      }
      EXPECT_TRUE(attachment->Submit(Answer(*frame)).ok());
    }
  };
  std::thread agent_a(answer, a->get(), true);
  std::thread agent_b(answer, b->get(), false);
  absl::SleepFor(absl::Milliseconds(100));  // every chance to advance wrongly
  EXPECT_EQ(lockstep_->tick(), 0u);
  // 0.05 s at 20 ms ticks: tick 3 (60 ms) is the first at or after it.
  EXPECT_EQ(lockstep_->FirstTickAtOrAfter(50'000'000), 3u);
  EXPECT_EQ(lockstep_->FirstTickAtOrAfter(60'000'000), 3u);
  EXPECT_EQ(lockstep_->RunUntil(3), 3u);
  absl::SleepFor(absl::Milliseconds(100));
  EXPECT_EQ(lockstep_->tick(), 3u);
  EXPECT_EQ(lockstep_->now_ns(), 60'000'000);
  EXPECT_EQ(lockstep_->RunUntil(10), 10u);
  ASSERT_EQ(a_names.size(), 10u);
  // The last frame before each hold says so (its agent then waits for fleetnavd).
  EXPECT_EQ(a_holds_after, (std::vector<uint64_t>{2, 9}));
  // fleetnavd's ticks name whom it waits for: the last of every 5 and the one before a hold.
  const std::vector<std::string> both{"a", "b"};
  for (uint64_t tick = 0; tick < 10; ++tick) {
    const bool servers = tick == 2 || tick == 4 || tick == 9;
    EXPECT_EQ(a_names[tick], servers ? both : std::vector<std::string>{}) << "tick " << tick;
  }
  stop.store(true);
  lockstep_->Stop();
  agent_a.join();
  agent_b.join();
}

}  // namespace
}  // namespace fleetnav::sim
