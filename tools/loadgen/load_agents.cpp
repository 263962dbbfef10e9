#include "load_agents.hpp"

#include <chrono>

namespace fleetnav::loadgen {

int64_t SteadyNowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

LoadAgent::LoadAgent(v1::AgentService::Stub* stub, std::string robot_id)
    : robot_id_(std::move(robot_id)) {
  v1::AgentHello* hello = hello_.mutable_hello();
  hello->set_robot_id(robot_id_);
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
  stub->async()->Connect(&context_, this);
  StartRead(&in_);
  StartWrite(&hello_);
  StartCall();
}

bool LoadAgent::Send(int64_t due_ns, uint64_t sequence) {
  if (done_.load() || !hello_done_.load()) return false;
  bool expected = false;
  if (!writing_.compare_exchange_strong(expected, true)) return false;
  due_ns_ = due_ns;
  v1::Telemetry* t = out_.mutable_telemetry();
  t->set_stamp_ns(due_ns);
  t->set_sequence(sequence);
  v1::Pose2* pose = t->mutable_pose_in_map()->mutable_pose();
  pose->set_x_m(static_cast<double>(sequence % 1000) * 0.01);
  pose->set_y_m(1.0);
  pose->set_yaw_rad(0.5);
  t->mutable_velocity()->set_vx_mps(0.25);
  t->set_mode(v1::NAVIGATION_MODE_STRAIGHT);
  t->set_battery_fraction(0.8);
  StartWrite(&out_);
  return true;
}

std::vector<double> LoadAgent::TakeLatencies() {
  std::lock_guard<std::mutex> lock(latencies_mutex_);
  std::vector<double> out;
  out.swap(latencies_ms_);
  return out;
}

void LoadAgent::OnWriteDone(bool ok) {
  if (!ok) return;
  if (!hello_done_.load()) {
    hello_done_.store(true);
  } else {
    completed_.fetch_add(1);
    std::lock_guard<std::mutex> lock(latencies_mutex_);
    latencies_ms_.push_back(static_cast<double>(SteadyNowNs() - due_ns_) * 1e-6);
  }
  writing_.store(false);
}

void LoadAgent::OnReadDone(bool ok) {
  if (ok) StartRead(&in_);
}

void LoadAgent::OnDone(const grpc::Status&) { done_.store(true); }

}  // namespace fleetnav::loadgen
