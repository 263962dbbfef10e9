#include "load_agents.hpp"

#include <grpcpp/create_channel.h>

#include <chrono>

namespace fleetnav::loadgen {
namespace {

gpr_timespec Deadline(int64_t steady_ns) {
  return gpr_time_add(
      gpr_now(GPR_CLOCK_MONOTONIC),
      gpr_time_from_nanos(std::max<int64_t>(0, steady_ns - SteadyNowNs()), GPR_TIMESPAN));
}

std::shared_ptr<grpc::Channel> NewAgentChannel(const LoadTarget& target, int index,
                                               const std::string& robot_id) {
  grpc::ChannelArguments args;
  args.SetInt(GRPC_ARG_ENABLE_RETRIES, 0);             // no retry buffering on long streams
  args.SetInt(GRPC_ARG_USE_LOCAL_SUBCHANNEL_POOL, 1);  // one connection per channel
  args.SetInt("fleetnav.loadgen.channel", index);
  return grpc::CreateCustomChannel(target.address, AgentCredentials(target, robot_id), args);
}

std::string RobotId(int index) { return "load-" + std::to_string(index); }

void FillHello(const std::string& robot_id, bool capable, v1::AgentMessage* message) {
  v1::AgentHello* hello = message->mutable_hello();
  hello->set_robot_id(robot_id);
  if (capable) hello->add_capabilities("straight");
  v1::RobotModel* model = hello->mutable_model();
  model->set_kind_name("loadgen");
  model->set_kinematics(v1::KINEMATICS_DIFFERENTIAL);
  for (auto [x, y] : {std::pair{0.5, 0.3}, {-0.5, 0.3}, {-0.5, -0.3}, {0.5, -0.3}}) {
    v1::Point2* corner = model->add_footprint();
    corner->set_x_m(x);
    corner->set_y_m(y);
  }
  model->set_wheel_radius_m(0.1);
  model->set_track_m(0.5);
  model->set_encoder_ticks_per_rev(1024);
  model->set_mass_kg(50);
  model->set_height_m(1);
  model->mutable_limits()->set_max_speed_mps(1.0);
  model->mutable_limits()->set_max_yaw_rate_radps(1.0);
  model->mutable_limits()->set_max_accel_mps2(1.0);
  model->mutable_limits()->set_max_yaw_accel_radps2(1.0);
  hello->set_software_version("loadgen");
}

/// Each agent stands in an aisle of its own, 3 m apart, facing along it.
void FillTelemetry(int index, v1::AgentMessage* message) {
  v1::Telemetry* t = message->mutable_telemetry();
  v1::Pose2* pose = t->mutable_pose_in_map()->mutable_pose();
  pose->set_x_m(0.0);
  pose->set_y_m(1.0 + 3.0 * index);
  pose->set_yaw_rad(0.5);
  t->mutable_velocity()->set_vx_mps(0.25);
  t->set_mode(v1::NAVIGATION_MODE_STRAIGHT);
  t->set_battery_fraction(0.8);
}

}  // namespace

int64_t SteadyNowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

int64_t DueOffsetNs(int index, int agents, int64_t period_ns) {
  return period_ns * index / std::max(agents, 1);
}

struct LoadWorker::Agent {
  grpc::ClientContext context;
  std::unique_ptr<grpc::ClientAsyncReaderWriter<v1::AgentMessage, v1::ServerMessage>> stream;
  v1::AgentMessage hello;
  v1::AgentMessage out;
  v1::ServerMessage in;
  grpc::Status status;
  int index = 0;          ///< of the agent in the whole run
  int64_t offset_ns = 0;  ///< due time within each period
  int64_t due_ns = 0;     ///< of the write in flight
  bool start_pending = true;
  bool hello_done = false;
  bool welcomed = false;
  bool writing = false;
  bool reading = false;
  bool broken = false;  ///< cancelled or failed: no more reads or writes
  bool finishing = false;
  bool finished = false;
};

LoadWorker::LoadWorker(WorkerParams params) : params_(std::move(params)) {
  // On TLS a connection carries one robot's certificate, so each agent has its own.
  const bool tls = !params_.target.tls_dir.empty();
  const int per_connection = tls ? 1 : std::max(1, params_.streams_per_connection);
  const int mine = static_cast<int>(params_.indices.size());
  const int channel_count = std::max(1, (mine + per_connection - 1) / per_connection);
  for (int c = 0; c < channel_count; ++c) {
    const std::string robot_id = RobotId(params_.indices[std::min(c, mine - 1)]);
    channels_.push_back(NewAgentChannel(params_.target, params_.first_channel_index + c, robot_id));
    stubs_.push_back(v1::AgentService::NewStub(channels_.back()));
  }
}

LoadWorker::~LoadWorker() { Stop(); }

void* LoadWorker::Tag(Agent* agent, Op op) {
  return reinterpret_cast<void*>(reinterpret_cast<uintptr_t>(agent) | static_cast<uintptr_t>(op));
}

int LoadWorker::Connect(int64_t deadline_ns) {
  for (size_t k = 0; k < params_.indices.size(); ++k) {
    const int index = params_.indices[k];
    auto agent = std::make_unique<Agent>();
    agent->offset_ns = 0;
    agent->index = index;
    FillHello(RobotId(index), index < params_.capable_agents, &agent->hello);
    FillTelemetry(index, &agent->out);
    // Neighbours in send order share a connection, so writes falling due together coalesce.
    const size_t channel = k * stubs_.size() / params_.indices.size();
    agent->stream = stubs_[channel]->PrepareAsyncConnect(&agent->context, &cq_);
    agent->stream->StartCall(Tag(agent.get(), Op::kStart));
    agents_.push_back(std::move(agent));
  }
  while (ready_ < static_cast<int>(agents_.size()) && SteadyNowNs() < deadline_ns) {
    Poll(deadline_ns, false);
  }
  return ready_;
}

void LoadWorker::Idle(int64_t until_ns) {
  while (SteadyNowNs() < until_ns) Poll(until_ns, false);
}

bool LoadWorker::Poll(int64_t deadline_ns, bool measuring) {
  void* tag = nullptr;
  bool ok = false;
  if (cq_.AsyncNext(&tag, &ok, Deadline(deadline_ns)) != grpc::CompletionQueue::GOT_EVENT) {
    return false;
  }
  const auto bits = reinterpret_cast<uintptr_t>(tag);
  Handle(reinterpret_cast<Agent*>(bits & ~uintptr_t{3}), static_cast<Op>(bits & 3), ok, measuring);
  return true;
}

void LoadWorker::Handle(Agent* agent, Op op, bool ok, bool measuring) {
  switch (op) {
    case Op::kStart:
      agent->start_pending = false;
      if (!ok || agent->broken) {
        agent->broken = true;
        break;
      }
      agent->writing = true;
      agent->stream->Write(agent->hello, Tag(agent, Op::kWrite));
      agent->reading = true;
      agent->stream->Read(&agent->in, Tag(agent, Op::kRead));
      break;
    case Op::kWrite:
      agent->writing = false;
      if (!ok) {
        agent->broken = true;
      } else if (!agent->hello_done) {
        agent->hello_done = true;
      } else if (measuring) {
        ++report_.delivered;
        report_.lag_ms.push_back(static_cast<double>(SteadyNowNs() - agent->due_ns) * 1e-6);
      }
      break;
    case Op::kRead:
      agent->reading = false;
      if (!ok) {
        agent->broken = true;
      } else if (!agent->broken) {
        if (!agent->welcomed) {  // the server has registered the robot
          agent->welcomed = true;
          ++ready_;
        }
        if (agent->in.has_stops() && agent->in.stops().stops_size() > 0) {
          report_.stops_heard.emplace_back(agent->index, SteadyNowNs());
        }
        agent->reading = true;
        agent->stream->Read(&agent->in, Tag(agent, Op::kRead));
      }
      break;
    case Op::kFinish:
      agent->finished = true;
      return;
  }
  MaybeFinish(agent);
}

void LoadWorker::MaybeFinish(Agent* agent) {
  if (!agent->broken || agent->finishing || agent->start_pending || agent->writing ||
      agent->reading) {
    return;
  }
  agent->finishing = true;
  agent->stream->Finish(&agent->status, Tag(agent, Op::kFinish));
}

void LoadWorker::Send(Agent* agent, int64_t due_ns, uint64_t sequence) {
  ++report_.scheduled;
  if (agent->broken || !agent->welcomed || agent->writing) {
    ++report_.skipped;
    return;
  }
  agent->due_ns = due_ns;
  v1::Telemetry* t = agent->out.mutable_telemetry();
  t->set_stamp_ns(due_ns);
  t->set_sequence(sequence);
  t->mutable_pose_in_map()->mutable_pose()->set_x_m(static_cast<double>(sequence % 1000) * 0.01);
  agent->writing = true;
  agent->stream->Write(agent->out, Tag(agent, Op::kWrite));
}

void LoadWorker::Run(int64_t start_ns, int64_t end_ns, int64_t period_ns, int64_t drain_until_ns) {
  for (size_t k = 0; k < agents_.size(); ++k) {
    agents_[k]->offset_ns = DueOffsetNs(params_.indices[k], params_.agents, period_ns);
  }
  size_t next = 0;
  uint64_t sequence = 0;
  for (int64_t tick_ns = start_ns; !agents_.empty() && tick_ns < end_ns;) {
    Agent* agent = agents_[next].get();
    const int64_t due_ns = tick_ns + agent->offset_ns;
    if (due_ns > SteadyNowNs()) {
      Poll(due_ns, true);  // reap completions until the next message falls due
      continue;
    }
    Send(agent, due_ns, sequence);
    if (++next == agents_.size()) {
      next = 0;
      tick_ns += period_ns;
      ++sequence;
    }
  }
  while (SteadyNowNs() < drain_until_ns) Poll(drain_until_ns, true);
}

void LoadWorker::Stop() {
  if (stopped_) return;
  stopped_ = true;
  for (auto& agent : agents_) {
    agent->broken = true;
    agent->context.TryCancel();
    MaybeFinish(agent.get());
  }
  for (auto& agent : agents_) {
    while (!agent->finished) Poll(SteadyNowNs() + 100'000'000, false);
  }
  cq_.Shutdown();
  void* tag = nullptr;
  bool ok = false;
  while (cq_.Next(&tag, &ok)) {
  }
  agents_.clear();
}

WorkerReport LoadWorker::TakeReport() {
  WorkerReport out = std::move(report_);
  out.connected = ready_;
  report_ = WorkerReport{};
  return out;
}

}  // namespace fleetnav::loadgen
