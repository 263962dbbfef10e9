#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "absl/synchronization/mutex.h"
#include "fleetnav/v1/agent_service.pb.h"

namespace fleetnav::server {

/// What the server does at each lockstep tick besides taking in the agents' messages.
struct TickWork {
  /// When the first lockstep stream joins, before its hello is answered: from now on the ticks
  /// drive the server's clock and its dispatcher.
  std::function<void()> first_join;
  /// Before the tick's messages: the server's clock goes to the tick's sim time.
  std::function<void(int64_t sim_time_ns)> begin;
  /// After them: the dispatcher pass, staleness, pose history that are due at the tick.
  std::function<void()> end;
};

/// The server's side of a simulated run's lockstep (docs/simulator.md, "Lockstep"). An agent in
/// lockstep sends its messages of a tick and then TickDone, naming the robots in the tick's
/// simulator barrier; it waits for the server's TickAck before the simulator may advance. The
/// barrier keeps each stream's messages until every named robot whose stream is open has ended
/// the tick, then takes them in robot by robot in id order, runs the tick's work with the
/// server's clock at the tick's sim time, and acknowledges the tick on each stream that ended
/// it, after whatever the tick made the server send. So what fleetnavd decides, and the tick at
/// which a robot hears it, is the same in every run whatever the machine's load. A stream that
/// ends leaves the barrier (its messages are taken in at once). Thread-safe; the handlers and
/// the work run under the barrier's lock, one tick at a time.
class TickBarrier {
 public:
  /// Takes in one message of a stream (as if it had just been read).
  using Handler = std::function<void(const v1::AgentMessage&)>;
  /// Sends the stream a TickAck for `tick`.
  using Acknowledger = std::function<void(uint64_t tick)>;

  explicit TickBarrier(TickWork work) : work_(std::move(work)) {}

  /// A stream of `robot_id` whose hello asked for lockstep, taking part from `from_tick` on (its
  /// agent answered the ticks before alone); it replaces an older stream of the same robot.
  /// Returns the member's key.
  uint64_t Join(const std::string& robot_id, uint64_t from_tick, Handler handle,
                Acknowledger acknowledge);
  /// Keeps a message of the member's current tick; false when the member has left (the caller
  /// then takes it in itself).
  bool Hold(uint64_t member, const v1::AgentMessage& message);
  /// The member has sent everything of `done.tick()`.
  void EndTick(uint64_t member, const v1::TickDone& done);
  /// The member's stream ended: what it sent is taken in now, and no tick waits for it.
  void Leave(uint64_t member);
  /// Whether an agent has ever taken part (the dispatcher then runs at the ticks).
  bool active() const;
  /// The last tick run, if any.
  std::optional<uint64_t> last_tick() const;

 private:
  struct Member {
    std::string robot_id;
    uint64_t from_tick = 0;  ///< no earlier tick waits for it
    Handler handle;
    Acknowledger acknowledge;
    std::vector<v1::AgentMessage> held;
    std::optional<v1::TickDone> done;  ///< the tick it ended and that has not run yet
  };
  /// Runs every tick whose robots have all ended it.
  void RunReadyTicks() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  void TakeIn(Member* member) ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);

  TickWork work_;
  mutable absl::Mutex mutex_;
  uint64_t next_key_ ABSL_GUARDED_BY(mutex_) = 1;
  std::map<uint64_t, Member> members_ ABSL_GUARDED_BY(mutex_);
  /// Each robot's one member (a new stream replaces the old), by robot id: the order ticks
  /// take the robots in.
  std::map<std::string, uint64_t> member_of_robot_ ABSL_GUARDED_BY(mutex_);
  bool active_ ABSL_GUARDED_BY(mutex_) = false;
  std::optional<uint64_t> last_tick_ ABSL_GUARDED_BY(mutex_);
};

}  // namespace fleetnav::server
