#include "fleetnav/sim/diff_drive_robot.hpp"

#include <algorithm>
#include <cmath>

namespace fleetnav::sim {
namespace {

struct Extent {
  double min_x, max_x, min_y, max_y;
};

Extent FootprintExtent(const RobotModel& model) {
  Extent e{1e9, -1e9, 1e9, -1e9};
  for (const Eigen::Vector2d& p : model.footprint_m) {
    e.min_x = std::min(e.min_x, p.x());
    e.max_x = std::max(e.max_x, p.x());
    e.min_y = std::min(e.min_y, p.y());
    e.max_y = std::max(e.max_y, p.y());
  }
  return e;
}

// Position of a point given in base_link (x forward, y left, z up) at the start pose.
void PlaceAt(dBodyID body, const Pose2& start, double x, double y, double z) {
  const Eigen::Vector2d p = start.TransformPoint({x, y});
  dBodySetPosition(body, p.x(), p.y(), z);
}

}  // namespace

DiffDriveRobot::DiffDriveRobot(OdeWorld* world, int robot_index, const RobotModel& model,
                               const Pose2& start, DiffDriveBodyParams params)
    : model_(model), params_(params), world_(world), robot_index_(robot_index) {
  const Extent extent = FootprintExtent(model);
  const double length = extent.max_x - extent.min_x;
  const double width = extent.max_y - extent.min_y;
  chassis_offset_x_m_ = 0.5 * (extent.max_x + extent.min_x);
  const double center_y = 0.5 * (extent.max_y + extent.min_y);
  chassis_z_m_ = params_.ground_clearance_m + 0.5 * params_.mass_box_height_m;

  dMatrix3 yaw_rotation;
  dRFromAxisAndAngle(yaw_rotation, 0, 0, 1, start.yaw_rad());

  chassis_ = dBodyCreate(world->world());
  dMass mass;
  dMassSetBoxTotal(&mass, model.mass_kg - 2 * params_.wheel_mass_kg, length, width,
                   params_.mass_box_height_m);
  dBodySetMass(chassis_, &mass);
  PlaceAt(chassis_, start, chassis_offset_x_m_, center_y, chassis_z_m_);
  dBodySetRotation(chassis_, yaw_rotation);

  // Collision box: the full body height, from the clearance up.
  dGeomID box = dCreateBox(world->space(), length, width, model.height_m);
  dGeomSetBody(box, chassis_);
  dGeomSetOffsetPosition(box, 0, 0,
                         params_.ground_clearance_m + 0.5 * model.height_m - chassis_z_m_);
  dGeomSetData(box, world->MakeTag(GeomRole::kChassis, robot_index));

  // A bumper skirt across the front, down to skirt_bottom_m: the body sits high on its wheels,
  // but its front bumper stops at low obstacles and platforms (it does not drive over them).
  const double skirt_height = params_.ground_clearance_m - params_.skirt_bottom_m;
  if (skirt_height > 0.0) {
    dGeomID skirt = dCreateBox(world->space(), 0.1, width, skirt_height);
    dGeomSetBody(skirt, chassis_);
    dGeomSetOffsetPosition(skirt, extent.max_x - 0.05 - chassis_offset_x_m_, 0,
                           params_.skirt_bottom_m + 0.5 * skirt_height - chassis_z_m_);
    dGeomSetData(skirt, world->MakeTag(GeomRole::kChassis, robot_index));
  }

  dGeomID caster = dCreateSphere(world->space(), params_.caster_radius_m);
  dGeomSetBody(caster, chassis_);
  dGeomSetOffsetPosition(caster, params_.caster_x_m - chassis_offset_x_m_, -center_y,
                         params_.caster_radius_m - chassis_z_m_);
  dGeomSetData(caster, world->MakeTag(GeomRole::kCaster, robot_index));

  const double axle_z = model.wheel_radius_m;
  left_wheel_ = CreateWheel(0.5 * model.track_m, start, axle_z);
  right_wheel_ = CreateWheel(-0.5 * model.track_m, start, axle_z);

  const Eigen::Vector2d axis = start.TransformPoint({0, 1}) - start.translation();
  for (auto [wheel, hinge_ptr, y] :
       {std::tuple{left_wheel_, &left_hinge_, 0.5 * model.track_m},
        std::tuple{right_wheel_, &right_hinge_, -0.5 * model.track_m}}) {
    dJointID hinge = dJointCreateHinge(world->world(), nullptr);
    dJointAttach(hinge, chassis_, wheel);
    const Eigen::Vector2d anchor = start.TransformPoint({0, y});
    dJointSetHingeAnchor(hinge, anchor.x(), anchor.y(), axle_z);
    // Axis to the left: a positive rate drives the wheel forward.
    dJointSetHingeAxis(hinge, axis.x(), axis.y(), 0);
    dJointSetHingeParam(hinge, dParamFMax, params_.max_wheel_torque_nm);
    dJointSetHingeParam(hinge, dParamVel, 0.0);
    *hinge_ptr = hinge;
  }
}

dBodyID DiffDriveRobot::CreateWheel(double y_m, const Pose2& start, double axle_z_m) {
  dBodyID wheel = dBodyCreate(world_->world());
  dMass mass;
  // Cylinder along its local z, turned to lie along base_link y.
  dMassSetCylinderTotal(&mass, params_.wheel_mass_kg, 3, model_.wheel_radius_m,
                        params_.wheel_width_m);
  dBodySetMass(wheel, &mass);
  PlaceAt(wheel, start, 0.0, y_m, axle_z_m);
  dMatrix3 rotation;
  dRFromZAxis(rotation, -std::sin(start.yaw_rad()), std::cos(start.yaw_rad()), 0);
  dBodySetRotation(wheel, rotation);
  // Contact geometry: a sphere touches the floor in one point on the wheel's mid-plane, as a tyre
  // patch does. A cylinder touches at both rims; the contact sticks at the outer rims and the
  // robot turns as if its track were track + wheel width (10 % slow on the Lely).
  dGeomID geom = dCreateSphere(world_->space(), model_.wheel_radius_m);
  dGeomSetBody(geom, wheel);
  dGeomSetData(geom, world_->MakeTag(GeomRole::kWheel, robot_index_));
  return wheel;
}

void DiffDriveRobot::SetWheelSpeeds(double left_radps, double right_radps) {
  // The hinge axis points left, so a forward-rolling wheel turns negatively about it.
  dJointSetHingeParam(left_hinge_, dParamVel, -left_radps);
  dJointSetHingeParam(right_hinge_, dParamVel, -right_radps);
  dBodyEnable(chassis_);
}

void DiffDriveRobot::SetTwist(const Twist2& twist) {
  const double half_track = 0.5 * model_.track_m;
  const double v_left = twist.vx_mps - twist.yaw_rate_radps * half_track;
  const double v_right = twist.vx_mps + twist.yaw_rate_radps * half_track;
  SetWheelSpeeds(v_left / model_.wheel_radius_m, v_right / model_.wheel_radius_m);
}

absl::Status DiffDriveRobot::SetDrive(const DriveCommand& drive, double scale) {
  if (const auto* twist = std::get_if<Twist2>(&drive)) {
    SetTwist(Twist2{scale * twist->vx_mps, 0.0, scale * twist->yaw_rate_radps});
  } else if (const auto* wheels = std::get_if<WheelSpeeds>(&drive)) {
    SetWheelSpeeds(scale * wheels->left_radps, scale * wheels->right_radps);
  } else {
    return absl::InvalidArgumentError("the robot is differential: Ackermann commands do not apply");
  }
  return absl::OkStatus();
}

void DiffDriveRobot::AfterStep(double step_s, double traction) {
  const double spin = traction > 0.0 ? 1.0 / traction : 1.0;
  left_angle_rad_ += -dJointGetHingeAngleRate(left_hinge_) * step_s * spin;
  right_angle_rad_ += -dJointGetHingeAngleRate(right_hinge_) * step_s * spin;
}

Pose2 DiffDriveRobot::GroundTruthPose() const {
  const dReal* r = dBodyGetRotation(chassis_);  // row-major 3x4
  const double yaw = std::atan2(r[4], r[0]);
  const dReal* p = dBodyGetPosition(chassis_);
  const Pose2 chassis_pose(p[0], p[1], yaw);
  return chassis_pose * Pose2(-chassis_offset_x_m_, 0.0, 0.0);
}

Twist2 DiffDriveRobot::GroundTruthVelocity() const {
  const Pose2 pose = GroundTruthPose();
  dVector3 v;
  const Eigen::Vector2d axle = pose.translation();
  dBodyGetPointVel(chassis_, axle.x(), axle.y(), model_.wheel_radius_m, v);
  const double c = std::cos(pose.yaw_rad()), s = std::sin(pose.yaw_rad());
  return Twist2{c * v[0] + s * v[1], -s * v[0] + c * v[1], yaw_rate_radps()};
}

double DiffDriveRobot::UpVectorZ() const { return dBodyGetRotation(chassis_)[10]; }

double DiffDriveRobot::yaw_rate_radps() const { return dBodyGetAngularVel(chassis_)[2]; }

}  // namespace fleetnav::sim
