#include "fleetnav/sim/lockstep.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>
#include <vector>

#include "absl/strings/str_cat.h"

namespace fleetnav::sim {

absl::Status LockstepParams::Validate() const {
  if (!(real_time_factor >= 0.0)) {
    return absl::InvalidArgumentError(
        absl::StrCat("real_time_factor: must be >= 0, got ", real_time_factor));
  }
  if (min_attached < 0) return absl::InvalidArgumentError("min_attached: must be >= 0");
  if (!(max_sim_time_s >= 0.0)) return absl::InvalidArgumentError("max_sim_time_s: must be >= 0");
  if (server_tick_every < 1) {
    return absl::InvalidArgumentError(
        absl::StrCat("server_tick_every: must be >= 1, got ", server_tick_every));
  }
  return absl::OkStatus();
}

Attachment::~Attachment() { owner_->Detach(robot_id_); }

std::optional<SensorFrame> Attachment::WaitFrame() { return owner_->WaitFrame(robot_id_); }

absl::Status Attachment::Submit(const ActuatorCommand& command) {
  return owner_->Submit(robot_id_, command);
}

Lockstep::Lockstep(Simulation* simulation, LockstepParams params)
    : simulation_(simulation), params_(params) {
  if (params.start_held) hold_at_tick_ = 0;
}

absl::StatusOr<std::unique_ptr<Attachment>> Lockstep::Attach(const std::string& robot_id) {
  absl::MutexLock lock(&mutex_);
  absl::StatusOr<RobotModel> model = simulation_->ModelOf(robot_id);
  if (!model.ok()) return model.status();
  if (slots_.count(robot_id) != 0) {
    return absl::FailedPreconditionError(
        absl::StrCat("robot '", robot_id, "' already has an agent attached"));
  }
  slots_[robot_id] = Slot{};
  return std::unique_ptr<Attachment>(new Attachment(this, robot_id));
}

void Lockstep::Detach(const std::string& robot_id) {
  absl::MutexLock lock(&mutex_);
  slots_.erase(robot_id);
  simulation_->StopDrive(robot_id);  // a robot without an agent stops; its lift holds
}

std::optional<SensorFrame> Lockstep::WaitFrame(const std::string& robot_id) {
  absl::MutexLock lock(&mutex_);
  auto has_frame = [&]() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_) {
    if (stopping_) return true;
    auto it = slots_.find(robot_id);
    return it == slots_.end() || (it->second.frame.has_value() && !it->second.taken);
  };
  mutex_.Await(absl::Condition(&has_frame));
  auto it = slots_.find(robot_id);
  if (stopping_ || it == slots_.end()) return std::nullopt;
  it->second.taken = true;
  return it->second.frame;
}

absl::Status Lockstep::Submit(const std::string& robot_id, const ActuatorCommand& command) {
  absl::MutexLock lock(&mutex_);
  auto it = slots_.find(robot_id);
  if (it == slots_.end()) return absl::FailedPreconditionError("not attached");
  Slot& slot = it->second;
  if (slot.stale_tick && command.tick == *slot.stale_tick &&
      (!slot.frame || command.tick != slot.frame->tick)) {
    slot.stale_tick.reset();
    return absl::OkStatus();  // the answer to a frame from before a reset
  }
  if (!slot.frame || command.tick != slot.frame->tick) {
    return absl::InvalidArgumentError(absl::StrCat(
        "command.tick: expected ", slot.frame ? slot.frame->tick : 0, ", got ", command.tick));
  }
  if (slot.answered) return absl::InvalidArgumentError("command: tick already answered");
  absl::Status status = simulation_->Command(robot_id, command);
  slot.answered = true;  // an invalid command still answers the tick (the robot keeps its last one)
  return status;
}

bool Lockstep::ReadyToTick() const {
  if (stopping_) return true;
  if (hold_at_tick_) return simulation_->tick() < *hold_at_tick_;
  if (requested_ticks_ > 0) return true;
  return static_cast<int>(slots_.size()) >= params_.min_attached && !slots_.empty();
}

bool Lockstep::AllAnswered() const {
  if (stopping_) return true;
  for (const auto& [id, slot] : slots_) {
    if (!slot.answered) return false;
  }
  return true;
}

void Lockstep::Run() {
  using Clock = std::chrono::steady_clock;
  Clock::time_point wall_start = Clock::now();
  int64_t sim_start_ns = now_ns();
  double rtf_in_force = 0.0;
  while (true) {
    absl::MutexLock lock(&mutex_);
    mutex_.Await(absl::Condition(this, &Lockstep::ReadyToTick));
    if (stopping_) break;
    if (params_.max_sim_time_s > 0.0 &&
        simulation_->now_ns() >= static_cast<int64_t>(params_.max_sim_time_s * 1e9)) {
      stopping_ = true;
      break;
    }
    // Hand out this tick's frames, then wait for every attached agent to answer.
    const TickHeader header = CurrentTickHeader();
    for (auto& [id, slot] : slots_) HandOutFrame(id, header, &slot);
    mutex_.Await(absl::Condition(this, &Lockstep::AllAnswered));
    if (stopping_) break;
    simulation_->Advance();
    if (tick_observer_) tick_observer_(*simulation_);
    if (requested_ticks_ > 0) --requested_ticks_;

    const double rtf = params_.real_time_factor;
    if (rtf != rtf_in_force) {  // restart the pacing reference when the factor changes
      rtf_in_force = rtf;
      wall_start = Clock::now();
      sim_start_ns = simulation_->now_ns();
    }
    if (rtf > 0.0) {
      const double sim_elapsed_s = static_cast<double>(simulation_->now_ns() - sim_start_ns) * 1e-9;
      const auto due = wall_start + std::chrono::duration_cast<Clock::duration>(
                                        std::chrono::duration<double>(sim_elapsed_s / rtf));
      mutex_.Unlock();
      std::this_thread::sleep_until(due);
      mutex_.Lock();
    }
  }
}

Lockstep::TickHeader Lockstep::CurrentTickHeader() const {
  const uint64_t tick = simulation_->tick();
  TickHeader header;
  header.holds_after = hold_at_tick_ && tick + 1 >= *hold_at_tick_;
  // Only fleetnavd's ticks name whom it waits for; on the others the agents report nothing of
  // the tick (what they send is taken in at fleetnavd's next tick).
  if (header.holds_after || (tick + 1) % static_cast<uint64_t>(params_.server_tick_every) == 0) {
    header.lockstep_robot_ids = AttachedIds();
  }
  return header;
}

void Lockstep::HandOutFrame(const std::string& robot_id, const TickHeader& header, Slot* slot) {
  absl::StatusOr<SensorFrame> frame = simulation_->Sense(robot_id);
  slot->frame = frame.ok() ? std::optional<SensorFrame>(*frame) : std::nullopt;
  if (slot->frame) {
    slot->frame->holds_after = header.holds_after;
    slot->frame->lockstep_robot_ids = header.lockstep_robot_ids;
  }
  slot->taken = false;
  slot->answered = !frame.ok();
}

std::vector<std::string> Lockstep::AttachedIds() const {
  std::vector<std::string> ids;
  for (const auto& [id, slot] : slots_) ids.push_back(id);  // a std::map: sorted
  return ids;
}

uint64_t Lockstep::RunUntil(uint64_t tick) {
  absl::MutexLock lock(&mutex_);
  hold_at_tick_ = tick;
  auto reached = [&]() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_) {
    return stopping_ || simulation_->tick() >= tick;
  };
  mutex_.Await(absl::Condition(&reached));
  return simulation_->tick();
}

uint64_t Lockstep::FirstTickAtOrAfter(int64_t sim_time_ns) const {
  absl::MutexLock lock(&mutex_);
  const double period_ns = simulation_->params().control_period_s * 1e9;
  auto tick = static_cast<uint64_t>(std::max(0.0, std::floor(sim_time_ns / period_ns)));
  // Tick times are rounded to whole nanoseconds: the estimate may be one off.
  while (simulation_->TimeOfTickNs(tick) < sim_time_ns) ++tick;
  while (tick > 0 && simulation_->TimeOfTickNs(tick - 1) >= sim_time_ns) --tick;
  return tick;
}

void Lockstep::SetTickObserver(std::function<void(const Simulation&)> observer) {
  absl::MutexLock lock(&mutex_);
  tick_observer_ = std::move(observer);
}

void Lockstep::Stop() {
  absl::MutexLock lock(&mutex_);
  stopping_ = true;
}

bool Lockstep::stopped() const {
  absl::MutexLock lock(&mutex_);
  return stopping_;
}

void Lockstep::RequestTicks(uint64_t ticks) {
  absl::MutexLock lock(&mutex_);
  requested_ticks_ += ticks;
}

void Lockstep::SetRealTimeFactor(double real_time_factor) {
  absl::MutexLock lock(&mutex_);
  params_.real_time_factor = real_time_factor;
}

absl::Status Lockstep::Spawn(const std::string& robot_id, const std::string& kind_name,
                             const Pose2& pose) {
  absl::MutexLock lock(&mutex_);
  return simulation_->AddRobot(robot_id, kind_name, pose);
}

absl::Status Lockstep::InjectFault(const FaultSpec& fault) {
  absl::MutexLock lock(&mutex_);
  return simulation_->InjectFault(fault);
}

void Lockstep::Reset(uint64_t seed) {
  absl::MutexLock lock(&mutex_);
  simulation_->Reset(seed);
  // Every agent still owing an answer gets the frame of tick 0 (the others get theirs with
  // the next tick).
  const TickHeader header = CurrentTickHeader();
  for (auto& [id, slot] : slots_) {
    if (slot.answered) continue;
    if (slot.frame && slot.taken) slot.stale_tick = slot.frame->tick;
    HandOutFrame(id, header, &slot);
  }
}

void Lockstep::Inspect(const std::function<void(const Simulation&)>& read) const {
  absl::MutexLock lock(&mutex_);
  read(*simulation_);
}

GroundTruthSnapshot Lockstep::GroundTruth() const {
  absl::MutexLock lock(&mutex_);
  return simulation_->GroundTruth();
}

uint64_t Lockstep::tick() const {
  absl::MutexLock lock(&mutex_);
  return simulation_->tick();
}

int64_t Lockstep::now_ns() const {
  absl::MutexLock lock(&mutex_);
  return simulation_->now_ns();
}

std::vector<std::string> Lockstep::attached_robot_ids() const {
  absl::MutexLock lock(&mutex_);
  return AttachedIds();
}

size_t Lockstep::attached_count() const {
  absl::MutexLock lock(&mutex_);
  return slots_.size();
}

}  // namespace fleetnav::sim
