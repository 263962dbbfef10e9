// TickBarrier without gRPC: members are closures that record what they were given.
#include "fleetnav/server/rpc/tick_barrier.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace fleetnav::server {
namespace {

v1::TickDone Done(uint64_t tick, const std::vector<std::string>& robots) {
  v1::TickDone done;
  done.set_tick(tick);
  done.set_sim_time_ns(static_cast<int64_t>(tick) * 20'000'000);
  for (const std::string& robot : robots) done.add_lockstep_robot_ids(robot);
  return done;
}

v1::AgentMessage Telemetry(int64_t stamp_ns) {
  v1::AgentMessage message;
  message.mutable_telemetry()->set_stamp_ns(stamp_ns);
  return message;
}

/// What the barrier did, in order: "begin T", "take ROBOT", "end", "ack ROBOT T".
class Journal {
 public:
  TickWork Work() {
    TickWork work;
    work.first_join = [this] { log.push_back("first join"); };
    work.begin = [this](int64_t ns) { log.push_back("begin " + std::to_string(ns / 20'000'000)); };
    work.end = [this] { log.push_back("end"); };
    return work;
  }
  uint64_t Join(TickBarrier* barrier, const std::string& robot, uint64_t from_tick = 0) {
    return barrier->Join(
        robot, from_tick,
        [this, robot](const v1::AgentMessage&) { log.push_back("take " + robot); },
        [this, robot](uint64_t tick) {
          log.push_back("ack " + robot + " " + std::to_string(tick));
        });
  }
  std::vector<std::string> log;
};

TEST(TickBarrierTest, ATickRunsOnceEveryNamedRobotEndedItTakingRobotsInIdOrder) {
  Journal journal;
  TickBarrier barrier(journal.Work());
  EXPECT_FALSE(barrier.active());
  const uint64_t b = journal.Join(&barrier, "b");
  const uint64_t a = journal.Join(&barrier, "a");
  EXPECT_TRUE(barrier.active());
  // b's stream delivers first, but a's messages are taken in first.
  ASSERT_TRUE(barrier.Hold(b, Telemetry(1)));
  barrier.EndTick(b, Done(5, {"a", "b"}));
  EXPECT_EQ(journal.log, (std::vector<std::string>{"first join"}));  // a has not ended tick 5
  EXPECT_FALSE(barrier.last_tick().has_value());
  ASSERT_TRUE(barrier.Hold(a, Telemetry(1)));
  barrier.EndTick(a, Done(5, {"a", "b"}));
  EXPECT_EQ(journal.log, (std::vector<std::string>{"first join", "begin 5", "take a", "take b",
                                                   "end", "ack a 5", "ack b 5"}));
  EXPECT_EQ(barrier.last_tick(), 5u);
}

TEST(TickBarrierTest, ARobotWithoutAStreamIsNotWaitedFor) {
  Journal journal;
  TickBarrier barrier(journal.Work());
  const uint64_t a = journal.Join(&barrier, "a");
  // b is in the simulator's barrier but not connected (a cut link): a's tick runs alone.
  barrier.EndTick(a, Done(7, {"a", "b"}));
  EXPECT_EQ(barrier.last_tick(), 7u);
  EXPECT_EQ(journal.log.back(), "ack a 7");
}

TEST(TickBarrierTest, AStreamThatEndsIsTakenInAndNoLongerWaitedFor) {
  Journal journal;
  TickBarrier barrier(journal.Work());
  const uint64_t a = journal.Join(&barrier, "a");
  const uint64_t b = journal.Join(&barrier, "b");
  ASSERT_TRUE(barrier.Hold(b, Telemetry(1)));
  barrier.EndTick(a, Done(3, {"a", "b"}));
  EXPECT_FALSE(barrier.last_tick().has_value());  // waits for b
  barrier.Leave(b);                               // b's agent was killed
  EXPECT_EQ(barrier.last_tick(), 3u);
  // b's message was taken in when it left, before the tick ran; b is not acknowledged.
  EXPECT_EQ(journal.log,
            (std::vector<std::string>{"first join", "take b", "begin 3", "end", "ack a 3"}));
  EXPECT_FALSE(barrier.Hold(b, Telemetry(2)));  // the caller takes it in itself
}

TEST(TickBarrierTest, ANewStreamOfARobotReplacesTheOldOne) {
  Journal journal;
  TickBarrier barrier(journal.Work());
  const uint64_t old_stream = journal.Join(&barrier, "a");
  ASSERT_TRUE(barrier.Hold(old_stream, Telemetry(1)));
  const uint64_t new_stream = journal.Join(&barrier, "a");
  EXPECT_NE(old_stream, new_stream);
  EXPECT_FALSE(barrier.Hold(old_stream, Telemetry(2)));
  barrier.EndTick(new_stream, Done(1, {"a"}));
  EXPECT_EQ(journal.log,
            (std::vector<std::string>{"first join", "take a", "begin 1", "end", "ack a 1"}));
}

// An agent already in the simulator's barrier when its stream reached the server ends a tick
// that ran without it: it is answered at once, and the others do not wait for it.
TEST(TickBarrierTest, AStreamEndingATickThatAlreadyRanIsAnsweredAtOnce) {
  Journal journal;
  TickBarrier barrier(journal.Work());
  const uint64_t a = journal.Join(&barrier, "a");
  barrier.EndTick(a, Done(0, {"a", "b"}));  // b not connected yet: tick 0 runs with a alone
  const uint64_t b = journal.Join(&barrier, "b");
  barrier.EndTick(b, Done(0, {"a", "b"}));
  EXPECT_EQ(journal.log.back(), "ack b 0");
  barrier.EndTick(a, Done(1, {"a", "b"}));
  EXPECT_EQ(barrier.last_tick(), 0u);  // tick 1 waits for b
  barrier.EndTick(b, Done(1, {"a", "b"}));
  EXPECT_EQ(barrier.last_tick(), 1u);
}

// An agent that answered tick 2 before its stream was live joins saying it takes part from tick
// 3 on. Its simulator waits for the others' command at tick 2, so tick 2 must not wait for it
// (it would wait for ever: the deadlock of a run whose agents start under load); what it sends
// now is tick 3's and is taken in at tick 3.
TEST(TickBarrierTest, AStreamIsNotWaitedForAtTicksItsAgentAnsweredBeforeItJoined) {
  Journal journal;
  TickBarrier barrier(journal.Work());
  const uint64_t a = journal.Join(&barrier, "a");
  const uint64_t b = journal.Join(&barrier, "b", /*from_tick=*/3);
  ASSERT_TRUE(barrier.Hold(b, Telemetry(3)));
  barrier.EndTick(a, Done(2, {"a", "b"}));
  EXPECT_EQ(barrier.last_tick(), 2u);
  EXPECT_EQ(journal.log, (std::vector<std::string>{"first join", "begin 2", "end", "ack a 2"}));
  barrier.EndTick(a, Done(3, {"a", "b"}));
  EXPECT_EQ(barrier.last_tick(), 2u);  // tick 3 waits for b
  barrier.EndTick(b, Done(3, {"a", "b"}));
  EXPECT_EQ(barrier.last_tick(), 3u);
  EXPECT_EQ(std::vector<std::string>(journal.log.begin() + 4, journal.log.end()),
            (std::vector<std::string>{"begin 3", "take b", "end", "ack a 3", "ack b 3"}));
}

}  // namespace
}  // namespace fleetnav::server
