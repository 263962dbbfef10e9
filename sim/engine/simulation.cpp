#include "fleetnav/sim/simulation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/status_macros.hpp"

namespace fleetnav::sim {
namespace {

using Clock = std::chrono::steady_clock;

double Seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

}  // namespace

absl::Status BatteryParams::Validate() const {
  if (!(initial_fraction >= 0.0 && initial_fraction <= 1.0)) {
    return absl::InvalidArgumentError("battery.initial_fraction: must be in [0, 1]");
  }
  for (double rate : {drain_per_s, drain_per_m, charge_per_s}) {
    if (!(std::isfinite(rate) && rate >= 0.0)) {
      return absl::InvalidArgumentError("battery rates: must be finite and >= 0");
    }
  }
  return absl::OkStatus();
}

absl::Status SimulationParams::Validate() const {
  if (!(physics_step_s > 0.0 && physics_step_s <= 0.005)) {
    return absl::InvalidArgumentError(
        absl::StrCat("physics_step_s: must be in (0, 0.005], got ", physics_step_s));
  }
  if (!(control_period_s >= physics_step_s && control_period_s <= 1.0)) {
    return absl::InvalidArgumentError(
        absl::StrCat("control_period_s: must be in [physics_step_s, 1], got ", control_period_s));
  }
  const double ratio = control_period_s / physics_step_s;
  if (std::abs(ratio - std::round(ratio)) > 1e-6) {
    return absl::InvalidArgumentError("control_period_s: must be a whole number of physics steps");
  }
  if (absl::Status s = battery.Validate(); !s.ok()) return s;
  if (absl::Status s = ackermann.Validate(); !s.ok()) {
    return absl::InvalidArgumentError(absl::StrCat("ackermann.", s.message()));
  }
  if (absl::Status s = mecanum.Validate(); !s.ok()) {
    return absl::InvalidArgumentError(absl::StrCat("mecanum.", s.message()));
  }
  return absl::OkStatus();
}

absl::StatusOr<std::unique_ptr<Simulation>> Simulation::Create(const WorldDescription& world,
                                                               SimulationParams params) {
  RETURN_IF_ERROR(params.Validate());
  for (size_t i = 0; i < world.faults.size(); ++i) {
    const FaultSpec& fault = world.faults[i];
    if (fault.type == FaultType::kSensorDropout || fault.type == FaultType::kSlowDown) {
      return absl::InvalidArgumentError(absl::StrCat(
          "faults[", i, "]: only region faults belong in a world file (inject robot faults)"));
    }
  }
  return std::unique_ptr<Simulation>(new Simulation(world, params));
}

Simulation::Simulation(const WorldDescription& world, SimulationParams params)
    : original_(world),
      params_(params),
      steps_per_tick_(
          static_cast<int>(std::lround(params.control_period_s / params.physics_step_s))),
      min_separation_m_(std::numeric_limits<double>::infinity()) {
  Build();
}

void Simulation::Build() {
  robots_.clear();
  index_.clear();
  contacts_.clear();
  touching_now_.clear();
  touching_last_.clear();
  episodes_.clear();
  faults_.clear();
  for (const FaultSpec& fault : original_.faults) faults_.push_back({fault, 0});
  tick_ = 0;
  min_separation_m_ = std::numeric_limits<double>::infinity();
  overlapping_.clear();
  description_ = original_;
  trolleys_.clear();
  world_ = std::make_unique<OdeWorld>(original_, params_.seed);
  for (size_t i = 0; i < original_.trolleys.size(); ++i) {
    trolleys_.push_back(
        std::make_unique<TrolleyBody>(world_.get(), static_cast<int>(i), original_.trolleys[i]));
  }
  ApplyWorldFaults();
}

void Simulation::ApplyWorldFaults() {
  description_ = original_;
  for (const ActiveFault& fault : faults_) {
    ApplyGeometryFault(fault.spec, &description_);
  }
  world_->SetStatics(description_);
  scene_static_valid_ = false;
}

void Simulation::Reset(uint64_t seed) {
  std::vector<std::tuple<std::string, std::string, Pose2>> spawns;
  for (const SimRobot& robot : robots_)
    spawns.emplace_back(robot.robot_id, robot.kind_name, robot.start);
  params_.seed = seed;
  Build();
  for (const auto& [id, kind, pose] : spawns) (void)CreateRobot(id, kind, pose);
}

absl::Status Simulation::AddRobot(const std::string& robot_id, const std::string& kind_name,
                                  const Pose2& pose) {
  if (robot_id.empty()) return absl::InvalidArgumentError("robot_id: empty");
  if (index_.count(robot_id) != 0) {
    return absl::AlreadyExistsError(absl::StrCat("robot '", robot_id, "' already exists"));
  }
  if (!pose.IsFinite()) return absl::InvalidArgumentError("pose: must be finite");
  return CreateRobot(robot_id, kind_name, pose);
}

absl::Status Simulation::CreateRobot(const std::string& robot_id, const std::string& kind_name,
                                     const Pose2& pose) {
  ASSIGN_OR_RETURN(RobotModel model, RobotModelByKind(kind_name));
  SimRobot robot;
  robot.robot_id = robot_id;
  robot.kind_name = kind_name;
  robot.start = pose;
  robot.battery_fraction = params_.battery.initial_fraction;
  const int index = static_cast<int>(robots_.size());
  if (model.kinematics == Kinematics::kDifferential) {
    robot.body = std::make_unique<DiffDriveRobot>(world_.get(), index, model, pose);
  } else if (model.kinematics == Kinematics::kOmnidirectional && !params_.kinematic_omni) {
    robot.body = std::make_unique<MecanumRobot>(world_.get(), index, model, pose,
                                                NoiseSeed(params_.seed, robot_id, "caster_swivel"),
                                                params_.mecanum);
  } else if (model.kinematics == Kinematics::kAckermann && !params_.kinematic_ackermann) {
    robot.body =
        std::make_unique<AckermannRobot>(world_.get(), index, model, pose, params_.ackermann);
  } else {
    auto body = std::make_unique<KinematicRobot>(world_.get(), index, model, pose);
    robot.kinematic = body.get();
    robot.body = std::move(body);
  }
  ProprioceptiveParams sensor_params = params_.sensors;
  sensor_params.encoder_ticks_per_rev = model.encoder_ticks_per_rev;
  robot.sensors = std::make_unique<ProprioceptiveSensors>(sensor_params, params_.seed, robot_id);
  robot.exteroceptive =
      std::make_unique<ExteroceptiveSensors>(model, params_.exteroceptive, params_.seed, robot_id);
  index_[robot_id] = robots_.size();
  robots_.push_back(std::move(robot));
  scene_robots_tick_ = ~uint64_t{0};
  return absl::OkStatus();
}

std::vector<std::string> Simulation::robot_ids() const {
  std::vector<std::string> ids;
  for (const SimRobot& robot : robots_) ids.push_back(robot.robot_id);
  return ids;
}

const RobotBody* Simulation::BodyOf(const std::string& robot_id) const {
  auto it = index_.find(robot_id);
  return it == index_.end() ? nullptr : robots_[it->second].body.get();
}

absl::StatusOr<RobotModel> Simulation::ModelOf(const std::string& robot_id) const {
  auto it = index_.find(robot_id);
  if (it == index_.end())
    return absl::NotFoundError(absl::StrCat("robot '", robot_id, "' not found"));
  return robots_[it->second].body->model();
}

int64_t Simulation::now_ns() const { return TimeOfTickNs(tick_); }

int64_t Simulation::TimeOfTickNs(uint64_t tick) const {
  return static_cast<int64_t>(
      std::llround(static_cast<double>(tick) * params_.control_period_s * 1e9));
}

void Simulation::EnsureScene() {
  if (!scene_static_valid_) {
    SensingScene fresh = StaticScene(description_);
    for (const ActiveFault& fault : faults_) {
      if (fault.spec.type == FaultType::kHideUltrasonicRegion) {
        fresh.ultrasonic_hidden.push_back(fault.spec);
      }
    }
    fresh.robots = std::move(scene_.robots);
    scene_ = std::move(fresh);
    scene_static_valid_ = true;
  }
  if (scene_robots_tick_ != tick_ ||
      scene_.robots.size() != robots_.size() + 4 * trolleys_.size()) {
    scene_.robots.clear();
    for (size_t i = 0; i < robots_.size(); ++i) {
      const RobotModel& model = robots_[i].body->model();
      scene_.robots.push_back(FootprintShape(model.footprint_m, robots_[i].body->GroundTruthPose(),
                                             model.height_m, static_cast<int>(i)));
    }
    // The trolleys' legs move too: after the robots, owned by no robot.
    for (const std::unique_ptr<TrolleyBody>& trolley : trolleys_) {
      for (const Shape2& leg : trolley->LegShapes()) scene_.robots.push_back(leg);
    }
    scene_robots_tick_ = tick_;
  }
}

std::set<std::string> Simulation::DroppedSensors(const std::string& robot_id) const {
  std::set<std::string> dropped;
  for (const ActiveFault& fault : faults_) {
    if (fault.spec.type == FaultType::kSensorDropout && fault.spec.robot_id == robot_id) {
      dropped.insert(fault.spec.sensor_name);
    }
  }
  return dropped;
}

absl::StatusOr<SensorFrame> Simulation::Sense(const std::string& robot_id) {
  auto it = index_.find(robot_id);
  if (it == index_.end())
    return absl::NotFoundError(absl::StrCat("robot '", robot_id, "' not found"));
  const Clock::time_point start = Clock::now();
  SimRobot& robot = robots_[it->second];
  SensorFrame frame;
  frame.tick = tick_;
  frame.stamp_ns = now_ns();
  frame.control_period_s = params_.control_period_s;
  const std::set<std::string> dropped = DroppedSensors(robot_id);
  robot.sensors->SampleEncoders(robot.body->WheelAngles(), &frame);
  robot.sensors->SampleSteering(robot.body->SteeringAngleRad(), &frame);
  const bool imu_off = dropped.count("imu") != 0 || dropped.count("") != 0;
  robot.sensors->SampleImu(imu_off ? 0.0 : robot.body->yaw_rate_radps(),
                           imu_off ? 0.0 : robot.accel_body.x(),
                           imu_off ? 0.0 : robot.accel_body.y(), params_.control_period_s, &frame);
  EnsureScene();
  robot.exteroceptive->Sample(scene_, static_cast<int>(it->second), robot.body->GroundTruthPose(),
                              tick_, params_.control_period_s, dropped, &frame);
  robot.charger_contact = frame.charger_contact;
  frame.lift_loaded = robot.carried_trolley >= 0;
  frame.battery_fraction = robot.battery_fraction;
  timing_.sensors_s += Seconds(Clock::now() - start);
  return frame;
}

absl::Status Simulation::Command(const std::string& robot_id, const ActuatorCommand& command) {
  auto it = index_.find(robot_id);
  if (it == index_.end())
    return absl::NotFoundError(absl::StrCat("robot '", robot_id, "' not found"));
  SimRobot& robot = robots_[it->second];
  if (command.lift_raised && !robot.body->model().has_lift) {
    return absl::InvalidArgumentError(absl::StrCat(
        "robot '", robot_id, "': a ", robot.body->model().kind_name, " has no lift to raise"));
  }
  absl::Status status = robot.body->SetDrive(command.drive, SlowFactor(robot_id));
  if (!status.ok()) {
    return absl::InvalidArgumentError(absl::StrCat("robot '", robot_id, "': ", status.message()));
  }
  robot.drive = command.drive;
  robot.lift_raised = command.lift_raised;
  return absl::OkStatus();
}

void Simulation::StopDrive(const std::string& robot_id) {
  auto it = index_.find(robot_id);
  if (it == index_.end()) return;
  ActuatorCommand stop;
  stop.lift_raised = robots_[it->second].lift_raised;
  (void)Command(robot_id, stop);
}

double Simulation::SlowFactor(const std::string& robot_id) const {
  double factor = 1.0;
  for (const ActiveFault& fault : faults_) {
    if (fault.spec.type == FaultType::kSlowDown && fault.spec.robot_id == robot_id) {
      factor *= fault.spec.factor;
    }
  }
  return factor;
}

double Simulation::TractionAt(const Pose2& pose) const {
  double traction = 1.0;
  for (const ActiveFault& fault : faults_) {
    if (fault.spec.type == FaultType::kWheelSlipRegion && fault.spec.InRegion(pose.translation())) {
      traction = std::min(traction, fault.spec.factor);
    }
  }
  return traction;
}

void Simulation::RecordContact(const std::string& robot_id, const std::string& other) {
  touching_now_.emplace(robot_id, other);
  contacts_.push_back({robot_id, other, now_ns()});
  if (contacts_.size() > 10000) contacts_.erase(contacts_.begin());
}

void Simulation::CountContactEpisodes() {
  for (const auto& pair : touching_now_) {
    if (touching_last_.count(pair) != 0) continue;
    std::pair<int, int>& counts = episodes_[pair.first];
    if (index_.count(pair.second) == 0) {  // "static" or a trolley
      ++counts.first;
    } else {
      ++counts.second;
    }
  }
  touching_last_.swap(touching_now_);
  touching_now_.clear();
}

void Simulation::MoveKinematic(SimRobot& robot, int index, double traction) {
  KinematicRobot& body = *robot.kinematic;
  const Pose2 next = body.Propose(params_.control_period_s, traction);
  const RobotModel& model = body.model();
  const Shape2 now_shape =
      FootprintShape(model.footprint_m, body.GroundTruthPose(), model.height_m, index);
  const Shape2 next_shape = FootprintShape(model.footprint_m, next, model.height_m, index);
  // Blocked by anything the robot would newly run into (it may always back out of an overlap).
  std::string hit;
  for (const Shape2& shape : scene_.statics) {
    if (Overlap(next_shape, shape) && !Overlap(now_shape, shape)) {
      hit = "static";
      break;
    }
  }
  for (size_t j = 0; j < robots_.size() && hit.empty(); ++j) {
    if (static_cast<int>(j) == index) continue;
    const RobotModel& other_model = robots_[j].body->model();
    const Shape2 other = FootprintShape(other_model.footprint_m, robots_[j].body->GroundTruthPose(),
                                        other_model.height_m, static_cast<int>(j));
    if (Overlap(next_shape, other) && !Overlap(now_shape, other)) hit = robots_[j].robot_id;
  }
  for (size_t j = 0; j < trolleys_.size() && hit.empty(); ++j) {
    if (static_cast<int>(j) == robot.carried_trolley) continue;
    for (const Shape2& leg : trolleys_[j]->LegShapes()) {
      if (Overlap(next_shape, leg) && !Overlap(now_shape, leg)) {
        hit = trolleys_[j]->id();
        break;
      }
    }
  }
  if (robot.carried_trolley >= 0 && hit.empty()) {
    // The carried trolley's legs move with the robot.
    const Pose2 moved = next * body.GroundTruthPose().Inverse();
    for (const Shape2& leg : trolleys_[static_cast<size_t>(robot.carried_trolley)]->LegShapes()) {
      const Shape2 next_leg =
          CircleShape(moved.TransformPoint(leg.center), leg.radius, leg.height_m, -1);
      for (const Shape2& shape : scene_.statics) {
        if (Overlap(next_leg, shape) && !Overlap(leg, shape)) hit = "static";
      }
    }
  }
  body.Commit(!hit.empty());
  if (!hit.empty()) RecordContact(robot.robot_id, hit);
}

void Simulation::UpdateLift(SimRobot& robot, int index) {
  if (!robot.lift_raised) {
    if (robot.carried_trolley >= 0) {
      trolleys_[static_cast<size_t>(robot.carried_trolley)]->Release();
      robot.carried_trolley = -1;
    }
    return;
  }
  if (robot.carried_trolley >= 0) return;
  const Pose2 at = robot.body->GroundTruthPose();
  for (size_t j = 0; j < trolleys_.size(); ++j) {
    TrolleyBody& trolley = *trolleys_[j];
    const Pose2 trolley_pose = trolley.pose();
    // The trolley is symmetric: either end may face the robot.
    const double yaw_off = std::abs(std::remainder(trolley_pose.yaw_rad() - at.yaw_rad(), kPi));
    if (trolley.carrier_robot_index() < 0 &&
        (trolley_pose.translation() - at.translation()).norm() <= kLatchRadiusM &&
        yaw_off <= kLatchYawRad) {
      trolley.Latch(robot.body->chassis_body(), index);
      robot.carried_trolley = static_cast<int>(j);
      return;
    }
  }
}

void Simulation::Advance() {
  const Clock::time_point start = Clock::now();
  EnsureScene();

  std::vector<double> traction(robots_.size(), 1.0);
  std::vector<Pose2> before(robots_.size());
  for (size_t i = 0; i < robots_.size(); ++i) before[i] = robots_[i].body->GroundTruthPose();
  for (size_t i = 0; i < robots_.size(); ++i) {
    SimRobot& robot = robots_[i];
    (void)robot.body->SetDrive(robot.drive, SlowFactor(robot.robot_id));
    UpdateLift(robot, static_cast<int>(i));
    traction[i] = TractionAt(robot.body->GroundTruthPose());
    if (robot.kinematic != nullptr) MoveKinematic(robot, static_cast<int>(i), traction[i]);
  }
  for (int s = 0; s < steps_per_tick_; ++s) {
    world_->Step(params_.physics_step_s);
    for (size_t i = 0; i < robots_.size(); ++i) {
      if (robots_[i].body->physical())
        robots_[i].body->AfterStep(params_.physics_step_s, traction[i]);
    }
    for (const ContactEvent& contact : world_->last_contacts()) {
      std::string other = "static";
      if (contact.other_trolley_index >= 0) {
        other = trolleys_[static_cast<size_t>(contact.other_trolley_index)]->id();
      } else if (contact.other_robot_index >= 0) {
        other = robots_[static_cast<size_t>(contact.other_robot_index)].robot_id;
      }
      RecordContact(robots_[contact.robot_index].robot_id, other);
    }
  }
  CountContactEpisodes();
  for (size_t i = 0; i < robots_.size(); ++i) {
    SimRobot& robot = robots_[i];
    const BatteryParams& b = params_.battery;
    const double moved_m =
        (robot.body->GroundTruthPose().translation() - before[i].translation()).norm();
    const double change =
        robot.charger_contact
            ? b.charge_per_s * params_.control_period_s
            : -(b.drain_per_s * params_.control_period_s + b.drain_per_m * moved_m);
    robot.battery_fraction = std::clamp(robot.battery_fraction + change, 0.0, 1.0);
  }
  ++tick_;
  // Faults that ran out leave before the next frames.
  const int64_t now = now_ns();
  bool world_changed = false;
  for (size_t i = 0; i < faults_.size();) {
    if (faults_[i].end_ns > 0 && faults_[i].end_ns <= now) {
      world_changed |= faults_[i].spec.IsRegionFault();
      faults_.erase(faults_.begin() + static_cast<std::ptrdiff_t>(i));
    } else {
      ++i;
    }
  }
  if (world_changed) ApplyWorldFaults();
  for (SimRobot& robot : robots_) {
    const Pose2 pose = robot.body->GroundTruthPose();
    const Twist2 v = robot.body->GroundTruthVelocity();
    const double c = std::cos(pose.yaw_rad()), s = std::sin(pose.yaw_rad());
    const Eigen::Vector2d world_velocity(c * v.vx_mps - s * v.vy_mps, s * v.vx_mps + c * v.vy_mps);
    const Eigen::Vector2d accel =
        (world_velocity - robot.world_velocity) / params_.control_period_s;
    robot.accel_body =
        Eigen::Vector2d(c * accel.x() + s * accel.y(), -s * accel.x() + c * accel.y());
    robot.world_velocity = world_velocity;
  }
  UpdateSeparation();
  timing_.physics_s += Seconds(Clock::now() - start);
  ++timing_.ticks;
}

absl::Status Simulation::InjectFault(const FaultSpec& fault) {
  if (!(fault.duration_s >= 0.0) || !std::isfinite(fault.duration_s)) {
    return absl::InvalidArgumentError("duration_s: must be finite and >= 0");
  }
  if (fault.IsRegionFault()) {
    if (!fault.region_min_m.allFinite() || !fault.region_max_m.allFinite() ||
        (fault.region_max_m - fault.region_min_m).minCoeff() <= 0.0) {
      return absl::InvalidArgumentError("region: max must exceed min in x and y");
    }
  } else {
    auto it = index_.find(fault.robot_id);
    if (it == index_.end()) {
      return absl::NotFoundError(absl::StrCat("robot_id: robot '", fault.robot_id, "' not found"));
    }
    if (fault.type == FaultType::kSensorDropout && !fault.sensor_name.empty() &&
        robots_[it->second].body->model().FindSensor(fault.sensor_name) == nullptr &&
        fault.sensor_name != "imu") {
      return absl::NotFoundError(absl::StrCat("sensor_name: robot '", fault.robot_id,
                                              "' has no sensor '", fault.sensor_name, "'"));
    }
  }
  if (fault.type == FaultType::kWheelSlipRegion && !(fault.factor > 0.0 && fault.factor <= 1.0)) {
    return absl::InvalidArgumentError(absl::StrCat(
        "factor: wheel slip keeps this share of traction, in (0, 1]; got ", fault.factor));
  }
  if (fault.type == FaultType::kSlowDown && !(fault.factor >= 0.0 && fault.factor <= 1.0)) {
    return absl::InvalidArgumentError(
        absl::StrCat("factor: slow-down must be in [0, 1]; got ", fault.factor));
  }
  const int64_t end_ns = fault.duration_s > 0.0
                             ? now_ns() + static_cast<int64_t>(std::llround(fault.duration_s * 1e9))
                             : 0;
  faults_.push_back({fault, end_ns});
  if (fault.IsRegionFault()) {
    if (fault.type == FaultType::kRemoveFenceSegment ||
        fault.type == FaultType::kRemoveStripeSegment) {
      ApplyWorldFaults();
    }
    scene_static_valid_ = false;
  }
  return absl::OkStatus();
}

std::vector<FaultSpec> Simulation::active_faults() const {
  std::vector<FaultSpec> out;
  for (const ActiveFault& fault : faults_) out.push_back(fault.spec);
  return out;
}

void Simulation::UpdateSeparation() {
  for (size_t i = 0; i < robots_.size(); ++i) {
    for (size_t j = i + 1; j < robots_.size(); ++j) {
      const RobotBody& a = *robots_[i].body;
      const RobotBody& b = *robots_[j].body;
      // The circumscribed circles bound the footprint distance from below: the exact polygon
      // distance is needed only when that bound could lower the minimum or mean contact.
      const double circle_distance =
          (a.GroundTruthPose().translation() - b.GroundTruthPose().translation()).norm() -
          a.model().CircumscribedRadius() - b.model().CircumscribedRadius();
      if (circle_distance >= min_separation_m_ && circle_distance > 0.0) {
        overlapping_.erase({i, j});
        continue;
      }
      const Shape2 shape_a = FootprintShape(a.model().footprint_m, a.GroundTruthPose(), 1.0, 0);
      const Shape2 shape_b = FootprintShape(b.model().footprint_m, b.GroundTruthPose(), 1.0, 1);
      const double distance = PolygonDistance(shape_a, shape_b);
      min_separation_m_ = std::min(min_separation_m_, distance);
      // Footprints that start to overlap are a robot-robot contact, whatever their heights.
      if (distance > 0.0) {
        overlapping_.erase({i, j});
      } else if (overlapping_.insert({i, j}).second) {
        RecordContact(robots_[i].robot_id, robots_[j].robot_id);
      }
    }
  }
}

GroundTruthSnapshot Simulation::GroundTruth() const {
  GroundTruthSnapshot out;
  out.tick = tick_;
  out.sim_time_ns = now_ns();
  for (const SimRobot& robot : robots_) {
    RobotTruth truth{robot.robot_id, robot.body->GroundTruthPose(),
                     robot.body->GroundTruthVelocity(), robot.body->UpVectorZ()};
    if (auto it = episodes_.find(robot.robot_id); it != episodes_.end()) {
      truth.collisions_world = it->second.first;
      truth.collisions_robots = it->second.second;
    }
    out.robots.push_back(truth);
  }
  for (const std::unique_ptr<TrolleyBody>& trolley : trolleys_) {
    const int carrier = trolley->carrier_robot_index();
    out.trolleys.push_back({trolley->id(), trolley->pose(),
                            carrier >= 0 ? robots_[static_cast<size_t>(carrier)].robot_id : ""});
  }
  out.contacts = contacts_;
  out.min_separation_m = min_separation_m_;
  return out;
}

}  // namespace fleetnav::sim
