#include "fleetnav/sim/trolley_body.hpp"

#include <cmath>

namespace fleetnav::sim {

TrolleyBody::TrolleyBody(OdeWorld* world, int trolley_index, const Trolley& trolley)
    : world_(world),
      size_m_(trolley.size_m),
      id_(trolley.id),
      leg_radius_m_(trolley.leg_radius_m),
      legs_in_trolley_(trolley.LegsInTrolley()) {
  body_ = dBodyCreate(world->world());
  dMass mass;
  dMassSetBoxTotal(&mass, kMassKg, trolley.size_m.x(), trolley.size_m.y(), kLegHeightM);
  dBodySetMass(body_, &mass);
  // The body's origin (its centre of mass) halfway up the legs.
  dBodySetPosition(body_, trolley.center_m.x(), trolley.center_m.y(), 0.5 * kLegHeightM);
  dMatrix3 rotation;
  dRFromAxisAndAngle(rotation, 0, 0, 1, trolley.yaw_rad);
  dBodySetRotation(body_, rotation);
  tag_ = world->MakeTag(GeomRole::kTrolley, -1);
  tag_->trolley_index = trolley_index;
  tag_->floor_mu = kCasterMu;
  for (const Eigen::Vector2d& leg : legs_in_trolley_) {
    // A capsule whose lower cap touches the floor: its length between the caps' centres.
    const double length_m = kLegHeightM - 2.0 * trolley.leg_radius_m;
    dGeomID geom = dCreateCapsule(world->space(), trolley.leg_radius_m, length_m);
    dGeomSetBody(geom, body_);
    dGeomSetOffsetPosition(geom, leg.x(), leg.y(), 0.0);
    dGeomSetData(geom, tag_);
  }
}

TrolleyBody::~TrolleyBody() {
  if (latch_ != nullptr) dJointDestroy(latch_);
}

void TrolleyBody::Latch(dBodyID carrier, int robot_index) {
  if (latch_ != nullptr) return;
  const dReal* p = dBodyGetPosition(body_);
  dBodySetPosition(body_, p[0], p[1], 0.5 * kLegHeightM + kLiftHeightM);
  const dReal* v = dBodyGetLinearVel(carrier);
  const dReal* w = dBodyGetAngularVel(carrier);
  dBodySetLinearVel(body_, v[0], v[1], 0.0);
  dBodySetAngularVel(body_, 0.0, 0.0, w[2]);
  latch_ = dJointCreateFixed(world_->world(), nullptr);
  dJointAttach(latch_, carrier, body_);
  dJointSetFixed(latch_);
  tag_->carrier_robot_index = robot_index;
}

void TrolleyBody::Release() {
  if (latch_ == nullptr) return;
  dJointDestroy(latch_);
  latch_ = nullptr;
  tag_->carrier_robot_index = -1;
  // Upright on its casters where it was carried to, at rest.
  const Pose2 at = pose();
  dBodySetPosition(body_, at.x_m(), at.y_m(), 0.5 * kLegHeightM);
  dMatrix3 rotation;
  dRFromAxisAndAngle(rotation, 0, 0, 1, at.yaw_rad());
  dBodySetRotation(body_, rotation);
  dBodySetLinearVel(body_, 0.0, 0.0, 0.0);
  dBodySetAngularVel(body_, 0.0, 0.0, 0.0);
}

Pose2 TrolleyBody::pose() const {
  const dReal* r = dBodyGetRotation(body_);  // row-major 3x4
  const dReal* p = dBodyGetPosition(body_);
  return Pose2(p[0], p[1], std::atan2(r[4], r[0]));
}

std::array<Shape2, 4> TrolleyBody::LegShapes() const {
  const Pose2 at = pose();
  std::array<Shape2, 4> out;
  for (size_t i = 0; i < 4; ++i) {
    out[i] = CircleShape(at.TransformPoint(legs_in_trolley_[i]), leg_radius_m_, kLegHeightM, -1);
  }
  return out;
}

}  // namespace fleetnav::sim
