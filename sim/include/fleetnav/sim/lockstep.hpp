#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/synchronization/mutex.h"
#include "fleetnav/sim/simulation.hpp"

namespace fleetnav::sim {

struct LockstepParams {
  /// Cap on sim time / wall time; 0 runs as fast as the agents answer.
  double real_time_factor = 0.0;
  /// Ticks advance on their own only while at least this many agents are attached.
  int min_attached = 1;
  /// Stop after this much sim time (0: never).
  double max_sim_time_s = 0.0;
  /// Start held at tick 0: ticks advance only as far as RunUntil asks.
  bool start_held = false;
  /// fleetnavd's tick: the agents report to it (their frames name the robots it waits for)
  /// every this many ticks, on the last tick of each period, and on the tick before a hold.
  /// 1 = every tick; the default, 5, is 100 ms at 20 ms ticks (the agents' telemetry rate).
  int server_tick_every = 5;
  absl::Status Validate() const;
};

class Lockstep;

/// One agent's side of the lockstep barrier for one robot: take the frame of each tick, answer
/// with a command for that tick. Detaches on destruction. Thread-safe against the loop.
class Attachment {
 public:
  ~Attachment();
  /// Blocks until the frame of the next tick is ready; nullopt when the simulation stops.
  std::optional<SensorFrame> WaitFrame();
  /// The command for the tick of the last frame; InvalidArgument for another tick.
  absl::Status Submit(const ActuatorCommand& command);
  const std::string& robot_id() const { return robot_id_; }

 private:
  friend class Lockstep;
  Attachment(Lockstep* owner, std::string robot_id)
      : owner_(owner), robot_id_(std::move(robot_id)) {}
  Lockstep* owner_;
  std::string robot_id_;
};

/// Barrier lockstep over a Simulation (ARCHITECTURE.md, "sim time is the only clock"): each
/// tick it hands every attached agent its sensor frame and advances only when every attached
/// agent has answered; an agent that detaches leaves the barrier and its robot stops. Each
/// frame names the robots in the tick's barrier, so that fleetnavd (to which the agents pass
/// them) knows whom to wait for. With real_time_factor > 0 the loop sleeps so that sim time runs
/// at most that much faster than wall time; RunUntil holds it at an exact tick. Thread-safe: Run()
/// on one thread, attachments and queries from any other.
class Lockstep {
 public:
  Lockstep(Simulation* simulation, LockstepParams params);

  /// FailedPrecondition if already attached, NotFound for an unknown robot.
  absl::StatusOr<std::unique_ptr<Attachment>> Attach(const std::string& robot_id);
  /// Runs ticks until Stop() or max_sim_time_s.
  void Run();
  void Stop();
  /// Advances `ticks` ticks now, whether or not min_attached agents are there.
  void RequestTicks(uint64_t ticks);
  /// Holds the simulation at `tick` (before its frames are handed out) and blocks until it is
  /// there or the loop stops; ticks advance meanwhile whatever min_attached says. Returns the
  /// tick reached. The hold stays until the next RunUntil.
  uint64_t RunUntil(uint64_t tick);
  /// The first tick whose sim time is at or after `sim_time_ns`.
  uint64_t FirstTickAtOrAfter(int64_t sim_time_ns) const;
  void SetRealTimeFactor(double real_time_factor);
  bool stopped() const;

  /// Adds a robot between ticks (see Simulation::AddRobot).
  absl::Status Spawn(const std::string& robot_id, const std::string& kind_name, const Pose2& pose);
  /// Puts a fault in force between ticks (see Simulation::InjectFault).
  absl::Status InjectFault(const FaultSpec& fault);
  /// Starts the simulation over with a new seed (see Simulation::Reset). Agents stay attached:
  /// an agent still owing an answer gets the frame of tick 0, and its answer to the frame from
  /// before the reset is ignored.
  void Reset(uint64_t seed);
  /// Calls `observer` after every tick, on the loop's thread, between ticks (recording).
  void SetTickObserver(std::function<void(const Simulation&)> observer);
  /// Runs `read` on the simulation between ticks.
  void Inspect(const std::function<void(const Simulation&)>& read) const;
  GroundTruthSnapshot GroundTruth() const;
  uint64_t tick() const;
  int64_t now_ns() const;
  size_t attached_count() const;
  /// The robots that have an agent attached, sorted.
  std::vector<std::string> attached_robot_ids() const;

 private:
  friend class Attachment;
  struct Slot {
    std::optional<SensorFrame> frame;  ///< the frame to hand out for the current tick
    bool taken = false;
    bool answered = true;                ///< a new agent joins the barrier at the next tick
    std::optional<uint64_t> stale_tick;  ///< the frame a reset replaced
  };
  void Detach(const std::string& robot_id);
  std::optional<SensorFrame> WaitFrame(const std::string& robot_id);
  absl::Status Submit(const std::string& robot_id, const ActuatorCommand& command);
  bool ReadyToTick() const ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  bool AllAnswered() const ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  /// What every frame of the current tick says besides its readings.
  struct TickHeader {
    std::vector<std::string> lockstep_robot_ids;  ///< on fleetnavd's ticks: whom it waits for
    bool holds_after = false;
  };
  TickHeader CurrentTickHeader() const ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  /// Senses the robot's frame for the current tick, with the tick's header.
  void HandOutFrame(const std::string& robot_id, const TickHeader& header, Slot* slot)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  std::vector<std::string> AttachedIds() const ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);

  Simulation* simulation_;
  mutable absl::Mutex mutex_;
  std::function<void(const Simulation&)> tick_observer_;
  LockstepParams params_ ABSL_GUARDED_BY(mutex_);
  std::map<std::string, Slot> slots_ ABSL_GUARDED_BY(mutex_);
  uint64_t requested_ticks_ ABSL_GUARDED_BY(mutex_) = 0;
  std::optional<uint64_t> hold_at_tick_ ABSL_GUARDED_BY(mutex_);
  bool stopping_ ABSL_GUARDED_BY(mutex_) = false;
};

}  // namespace fleetnav::sim
