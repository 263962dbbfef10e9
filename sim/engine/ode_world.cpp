#include "fleetnav/sim/ode_world.hpp"

#include <cmath>
#include <mutex>

namespace fleetnav::sim {
namespace {

constexpr int kMaxContactsPerPair = 8;

// ODE keeps process-wide state; initialise it once and keep it for the process's life.
void EnsureOdeInitialised() {
  static std::once_flag once;
  std::call_once(once, [] { dInitODE2(0); });
}

uint64_t SplitMix64(uint64_t* state) {
  uint64_t z = (*state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

const GeomTag* TagOf(dGeomID geom) { return static_cast<const GeomTag*>(dGeomGetData(geom)); }

}  // namespace

OdeWorld::OdeWorld(const WorldDescription& description, uint64_t seed) : rng_state_(seed) {
  EnsureOdeInitialised();
  world_ = dWorldCreate();
  space_ = dHashSpaceCreate(nullptr);
  contact_group_ = dJointGroupCreate(0);
  dWorldSetGravity(world_, 0, 0, -9.81);
  dWorldSetERP(world_, 0.2);
  dWorldSetCFM(world_, 1e-7);
  dWorldSetContactSurfaceLayer(world_, 0.001);

  dGeomID ground = dCreatePlane(space_, 0, 0, 1, 0);
  dGeomSetData(ground, MakeTag(GeomRole::kGround, -1));
  static_tag_ = MakeTag(GeomRole::kStatic, -1);
  SetStatics(description);
}

void OdeWorld::SetStatics(const WorldDescription& description) {
  for (dGeomID geom : statics_) dGeomDestroy(geom);
  statics_.clear();
  for (const BoxObstacle& box : description.boxes) {
    dGeomID geom = dCreateBox(space_, box.size_m.x(), box.size_m.y(), box.height_m);
    dGeomSetPosition(geom, box.center_m.x(), box.center_m.y(), 0.5 * box.height_m);
    dMatrix3 rotation;
    dRFromAxisAndAngle(rotation, 0, 0, 1, box.yaw_rad);
    dGeomSetRotation(geom, rotation);
    dGeomSetData(geom, static_tag_);
    statics_.push_back(geom);
  }
  for (const CylinderObstacle& cylinder : description.cylinders) {
    dGeomID geom = dCreateCylinder(space_, cylinder.radius_m, cylinder.height_m);
    dGeomSetPosition(geom, cylinder.center_m.x(), cylinder.center_m.y(), 0.5 * cylinder.height_m);
    dGeomSetData(geom, static_tag_);
    statics_.push_back(geom);
  }
}

OdeWorld::~OdeWorld() {
  dJointGroupDestroy(contact_group_);
  dSpaceDestroy(space_);  // destroys the geoms it holds
  dWorldDestroy(world_);  // destroys bodies and joints
}

GeomTag* OdeWorld::MakeTag(GeomRole role, int robot_index) {
  tags_.push_back(GeomTag{role, robot_index});
  return &tags_.back();
}

void OdeWorld::Step(double step_s) {
  contacts_.clear();
  step_s_ = step_s;
  dSpaceCollide(space_, this, &OdeWorld::NearCallback);
  dRandSetSeed(static_cast<unsigned long>(SplitMix64(&rng_state_)));
  // The exact (Dantzig LCP) step, not dWorldQuickStep: the iterative solver leaves part of the
  // chassis's pitch moment on the wheel motors, and a robot commanded to stand still crept
  // backwards at ~1.3 mm/s. A few bodies per robot keep the exact step cheap.
  dWorldStep(world_, step_s);
  dJointGroupEmpty(contact_group_);
}

void OdeWorld::ApplyWheelContact(const GeomTag& wheel, bool wheel_first, dContact* contact) const {
  dSurfaceParameters& surface = contact->surface;
  const DirectionalFriction& friction = wheel.friction;
  if (friction.frame != nullptr) {
    dVector3 axis;
    dBodyVectorToWorld(friction.frame, friction.axis_x, friction.axis_y, 0.0, axis);
    const dReal* n = contact->geom.normal;
    const double along_normal = axis[0] * n[0] + axis[1] * n[1] + axis[2] * n[2];
    double d[3] = {axis[0] - along_normal * n[0], axis[1] - along_normal * n[1],
                   axis[2] - along_normal * n[2]};
    const double norm = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (norm > 1e-9) {
      surface.mode |= dContactMu2 | dContactFDir1;
      for (int k = 0; k < 3; ++k) contact->fdir1[k] = d[k] / norm;
      surface.mu = friction.mu_along;
      surface.mu2 = friction.mu_across;
      if (friction.surface_speed_mps != 0.0) {
        surface.mode |= dContactMotion1;
        // motion1 is the first body's surface speed relative to the second's.
        surface.motion1 = wheel_first ? friction.surface_speed_mps : -friction.surface_speed_mps;
      }
      if (friction.creep_mps_per_n > 0.0) {
        surface.mode |= dContactSlip1;
        surface.slip1 = friction.creep_mps_per_n;
      }
    }
  }
  if (wheel.contact_spring_npm > 0.0) {
    // ODE's spring-damper contact: ERP = h k / (h k + c), CFM = 1 / (h k + c).
    const double hk = step_s_ * wheel.contact_spring_npm;
    const double denominator = hk + wheel.contact_damper_nspm;
    surface.soft_erp = hk / denominator;
    surface.soft_cfm = 1.0 / denominator;
  }
}

void OdeWorld::NearCallback(void* data, dGeomID a, dGeomID b) {
  static_cast<OdeWorld*>(data)->HandlePair(a, b);
}

void OdeWorld::HandlePair(dGeomID a, dGeomID b) {
  const GeomTag* tag_a = TagOf(a);
  const GeomTag* tag_b = TagOf(b);
  if (tag_a == nullptr || tag_b == nullptr) return;
  const bool a_static = tag_a->role == GeomRole::kGround || tag_a->role == GeomRole::kStatic;
  const bool b_static = tag_b->role == GeomRole::kGround || tag_b->role == GeomRole::kStatic;
  if (a_static && b_static) return;
  // A robot's (or a trolley's) own parts never collide with each other.
  if (!a_static && !b_static && tag_a->robot_index == tag_b->robot_index &&
      tag_a->trolley_index == tag_b->trolley_index) {
    return;
  }
  // A carried trolley rests on its carrier's lift, clear of the floor and of the carrier.
  const int carrier_a = tag_a->carrier_robot_index;
  const int carrier_b = tag_b->carrier_robot_index;
  if (carrier_a >= 0 && (tag_b->role == GeomRole::kGround || tag_b->robot_index == carrier_a)) {
    return;
  }
  if (carrier_b >= 0 && (tag_a->role == GeomRole::kGround || tag_a->robot_index == carrier_b)) {
    return;
  }

  // Kinematic bodies (omni, Ackermann) and static geoms are not moved by contacts: a pair
  // without a dynamic body needs no contact joint, and the simulation reports the kinematic
  // robots' contacts itself.
  const dBodyID body_a = dGeomGetBody(a);
  const dBodyID body_b = dGeomGetBody(b);
  const bool dynamic_a = body_a != nullptr && !dBodyIsKinematic(body_a);
  const bool dynamic_b = body_b != nullptr && !dBodyIsKinematic(body_b);
  if (!dynamic_a && !dynamic_b) return;

  dContact contacts[kMaxContactsPerPair];
  const int count = dCollide(a, b, kMaxContactsPerPair, &contacts[0].geom, sizeof(dContact));
  if (count == 0) return;

  const bool caster = tag_a->role == GeomRole::kCaster || tag_b->role == GeomRole::kCaster;
  const bool wheel = tag_a->role == GeomRole::kWheel || tag_b->role == GeomRole::kWheel;
  double mu = 0.4;
  if (caster) mu = 0.0;  // a swivel caster carries load but resists no direction
  if (wheel) mu = 1.0;
  // A geom on the floor may have a friction of its own; a wheel may grip differently by
  // direction, and may be sprung.
  const GeomTag* on_floor = nullptr;
  if (tag_b->role == GeomRole::kGround) on_floor = tag_a;
  if (tag_a->role == GeomRole::kGround) on_floor = tag_b;
  if (on_floor != nullptr && on_floor->floor_mu >= 0.0) mu = on_floor->floor_mu;
  const bool on_floor_first = on_floor == tag_a;

  for (int i = 0; i < count; ++i) {
    dSurfaceParameters& surface = contacts[i].surface;
    surface.mode = dContactApprox1 | dContactSoftCFM | dContactSoftERP;
    surface.mu = mu;
    surface.soft_cfm = 1e-6;
    surface.soft_erp = 0.3;
    if (on_floor != nullptr) ApplyWheelContact(*on_floor, on_floor_first, &contacts[i]);
    dJointID joint = dJointCreateContact(world_, contact_group_, &contacts[i]);
    dJointAttach(joint, dGeomGetBody(a), dGeomGetBody(b));
  }
  // What a carried trolley touches, its carrier touches.
  if (carrier_a >= 0) contacts_.push_back({carrier_a, tag_b->robot_index, tag_b->trolley_index});
  if (carrier_b >= 0) contacts_.push_back({carrier_b, tag_a->robot_index, tag_a->trolley_index});
  if (tag_a->role == GeomRole::kChassis || tag_b->role == GeomRole::kChassis) {
    const bool a_is_robot = tag_a->role == GeomRole::kChassis && dynamic_a;
    if (!a_is_robot && !(tag_b->role == GeomRole::kChassis && dynamic_b)) return;
    const GeomTag* robot = a_is_robot ? tag_a : tag_b;
    const GeomTag* other = robot == tag_a ? tag_b : tag_a;
    if (other->role == GeomRole::kTrolley) {
      contacts_.push_back({robot->robot_index, -1, other->trolley_index});
    } else if (other->role != GeomRole::kGround) {
      contacts_.push_back({robot->robot_index, other->robot_index});
    }
  }
}

}  // namespace fleetnav::sim
