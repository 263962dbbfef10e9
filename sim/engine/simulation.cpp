#include "fleetnav/sim/simulation.hpp"

#include <cmath>
#include <limits>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/status_macros.hpp"

namespace fleetnav::sim {

absl::Status SimulationParams::Validate() const {
  if (!(physics_step_s > 0.0 && physics_step_s <= 0.005)) {
    return absl::InvalidArgumentError(
        absl::StrCat("physics_step_s: must be in (0, 0.005], got ", physics_step_s));
  }
  if (!(control_period_s >= physics_step_s && control_period_s <= 1.0)) {
    return absl::InvalidArgumentError(absl::StrCat(
        "control_period_s: must be in [physics_step_s, 1], got ", control_period_s));
  }
  const double ratio = control_period_s / physics_step_s;
  if (std::abs(ratio - std::round(ratio)) > 1e-6) {
    return absl::InvalidArgumentError(
        "control_period_s: must be a whole number of physics steps");
  }
  return absl::OkStatus();
}

absl::StatusOr<std::unique_ptr<Simulation>> Simulation::Create(const WorldDescription& world,
                                                               SimulationParams params) {
  RETURN_IF_ERROR(params.Validate());
  return std::unique_ptr<Simulation>(new Simulation(world, params));
}

Simulation::Simulation(const WorldDescription& world, SimulationParams params)
    : description_(world),
      params_(params),
      world_(std::make_unique<OdeWorld>(world, params.seed)),
      steps_per_tick_(static_cast<int>(std::lround(params.control_period_s / params.physics_step_s))),
      min_separation_m_(std::numeric_limits<double>::infinity()) {}

absl::Status Simulation::AddRobot(const std::string& robot_id, const std::string& kind_name,
                                  const Pose2& pose) {
  if (robot_id.empty()) return absl::InvalidArgumentError("robot_id: empty");
  if (index_.count(robot_id) != 0) {
    return absl::AlreadyExistsError(absl::StrCat("robot '", robot_id, "' already exists"));
  }
  if (!pose.IsFinite()) return absl::InvalidArgumentError("pose: must be finite");
  ASSIGN_OR_RETURN(RobotModel model, RobotModelByKind(kind_name));
  if (model.kinematics != Kinematics::kDifferential) {
    return absl::UnimplementedError(absl::StrCat(
        "kind '", kind_name, "': only differential-drive robots are simulated in this version"));
  }
  SimRobot robot;
  robot.robot_id = robot_id;
  robot.body = std::make_unique<DiffDriveRobot>(world_.get(), static_cast<int>(robots_.size()),
                                                model, pose);
  ProprioceptiveParams sensor_params = params_.sensors;
  sensor_params.encoder_ticks_per_rev = model.encoder_ticks_per_rev;
  robot.sensors = std::make_unique<ProprioceptiveSensors>(sensor_params, params_.seed, robot_id);
  index_[robot_id] = robots_.size();
  robots_.push_back(std::move(robot));
  return absl::OkStatus();
}

std::vector<std::string> Simulation::robot_ids() const {
  std::vector<std::string> ids;
  for (const SimRobot& robot : robots_) ids.push_back(robot.robot_id);
  return ids;
}

absl::StatusOr<RobotModel> Simulation::ModelOf(const std::string& robot_id) const {
  auto it = index_.find(robot_id);
  if (it == index_.end()) return absl::NotFoundError(absl::StrCat("robot '", robot_id, "' not found"));
  return robots_[it->second].body->model();
}

int64_t Simulation::now_ns() const {
  return static_cast<int64_t>(std::llround(static_cast<double>(tick_) * params_.control_period_s * 1e9));
}

absl::StatusOr<SensorFrame> Simulation::Sense(const std::string& robot_id) {
  auto it = index_.find(robot_id);
  if (it == index_.end()) return absl::NotFoundError(absl::StrCat("robot '", robot_id, "' not found"));
  SimRobot& robot = robots_[it->second];
  SensorFrame frame;
  frame.tick = tick_;
  frame.stamp_ns = now_ns();
  frame.control_period_s = params_.control_period_s;
  robot.sensors->Sample(robot.body->left_wheel_angle_rad(), robot.body->right_wheel_angle_rad(),
                        robot.body->yaw_rate_radps(), params_.control_period_s, &frame);
  return frame;
}

absl::Status Simulation::Command(const std::string& robot_id, const ActuatorCommand& command) {
  auto it = index_.find(robot_id);
  if (it == index_.end()) return absl::NotFoundError(absl::StrCat("robot '", robot_id, "' not found"));
  DiffDriveRobot& body = *robots_[it->second].body;
  if (const auto* twist = std::get_if<Twist2>(&command.drive)) {
    body.SetTwist(*twist);
  } else if (const auto* wheels = std::get_if<WheelSpeeds>(&command.drive)) {
    body.SetWheelSpeeds(wheels->left_radps, wheels->right_radps);
  } else {
    return absl::InvalidArgumentError(
        absl::StrCat("robot '", robot_id, "' is differential: Ackermann commands do not apply"));
  }
  return absl::OkStatus();
}

void Simulation::Advance() {
  for (int i = 0; i < steps_per_tick_; ++i) {
    world_->Step(params_.physics_step_s);
    for (SimRobot& robot : robots_) robot.body->AfterStep(params_.physics_step_s);
    for (const ContactEvent& contact : world_->last_contacts()) {
      contacts_.push_back({robots_[contact.robot_index].robot_id,
                           contact.other_robot_index < 0
                               ? std::string("static")
                               : robots_[contact.other_robot_index].robot_id,
                           now_ns()});
      if (contacts_.size() > 10000) contacts_.erase(contacts_.begin());
    }
  }
  ++tick_;
  UpdateSeparation();
}

void Simulation::UpdateSeparation() {
  for (size_t i = 0; i < robots_.size(); ++i) {
    for (size_t j = i + 1; j < robots_.size(); ++j) {
      const DiffDriveRobot& a = *robots_[i].body;
      const DiffDriveRobot& b = *robots_[j].body;
      const double distance =
          (a.GroundTruthPose().translation() - b.GroundTruthPose().translation()).norm() -
          a.model().CircumscribedRadius() - b.model().CircumscribedRadius();
      min_separation_m_ = std::min(min_separation_m_, distance);
    }
  }
}

GroundTruthSnapshot Simulation::GroundTruth() const {
  GroundTruthSnapshot out;
  out.tick = tick_;
  out.sim_time_ns = now_ns();
  for (const SimRobot& robot : robots_) {
    out.robots.push_back({robot.robot_id, robot.body->GroundTruthPose(),
                          robot.body->GroundTruthVelocity(), robot.body->UpVectorZ()});
  }
  out.contacts = contacts_;
  out.min_separation_m = min_separation_m_;
  return out;
}

}  // namespace fleetnav::sim
