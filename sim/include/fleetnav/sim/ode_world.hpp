#pragma once

#include <ode/ode.h>

#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "fleetnav/sim/world_description.hpp"

namespace fleetnav::sim {

/// What a geom is, for contact parameters (friction per pair) and contact reports.
enum class GeomRole : uint8_t { kGround, kStatic, kChassis, kWheel, kCaster, kTrolley };

/// Friction of a wheel's floor contact that differs by direction: a mecanum wheel's roller
/// turns freely across its axle and grips along it; a caster wheel rolls along its plane and
/// grips across it. `axis_*` is the gripping direction in the frame of `frame` (the body the
/// direction turns with), `mu_along` the friction along it and `mu_across` across it (ODE's
/// fdir1, mu and mu2).
struct DirectionalFriction {
  dBodyID frame = nullptr;  ///< nullptr: isotropic friction
  double axis_x = 1.0;
  double axis_y = 0.0;
  double mu_along = 1.0;
  double mu_across = 0.0;
  /// Creep along the gripping direction: slip speed per newton of force (ODE's
  /// force-dependent slip, the usual tyre model); 0 = none.
  double creep_mps_per_n = 0.0;
  /// Speed of the wheel's surface along the gripping direction (ODE's motion1): a driven wheel
  /// modelled as a contact of its carrier rather than a body of its own.
  double surface_speed_mps = 0.0;
};

struct GeomTag {
  GeomRole role = GeomRole::kStatic;
  int robot_index = -1;    ///< for robot geoms
  int trolley_index = -1;  ///< for trolley geoms
  /// For a latched trolley's geoms: the robot carrying it (its contacts are that robot's).
  int carrier_robot_index = -1;
  /// Friction against the floor when set (>= 0), e.g. a trolley leg's swivel caster; else the
  /// role's default.
  double floor_mu = -1.0;
  DirectionalFriction friction;
  /// A sprung floor contact (a suspended wheel): spring and damper of the contact's
  /// penetration; 0 uses the world's stiff contact.
  double contact_spring_npm = 0.0;
  double contact_damper_nspm = 0.0;
};

/// A contact between a robot's chassis and something else seen in the last step.
struct ContactEvent {
  int robot_index = -1;
  int other_robot_index = -1;    ///< -1: a static obstacle or a trolley
  int other_trolley_index = -1;  ///< a trolley's leg
};

/// The ODE physics world of one simulation: world, collision space, contact group, a ground
/// plane and the static obstacles of a WorldDescription. Owns every ODE handle (RAII). Step()
/// uses ODE's exact solver (dWorldStep) so that resting contacts hold; it still reseeds ODE's
/// global random generator (dRandSetSeed) from the simulation's own seed stream before each
/// step, so runs stay reproducible whatever ODE draws from it. Not thread-safe: one simulation
/// thread drives it.
class OdeWorld {
 public:
  OdeWorld(const WorldDescription& description, uint64_t seed);
  ~OdeWorld();
  OdeWorld(const OdeWorld&) = delete;
  OdeWorld& operator=(const OdeWorld&) = delete;

  dWorldID world() const { return world_; }
  dSpaceID space() const { return space_; }
  /// Tags are owned by the world and live as long as it does.
  GeomTag* MakeTag(GeomRole role, int robot_index);

  /// Replaces the static obstacles with the world's (after a fault took a fence segment away).
  void SetStatics(const WorldDescription& description);

  /// Collides, integrates one step of `step_s`, and records chassis contacts.
  void Step(double step_s);
  const std::vector<ContactEvent>& last_contacts() const { return contacts_; }

 private:
  static void NearCallback(void* data, dGeomID a, dGeomID b);
  void HandlePair(dGeomID a, dGeomID b);
  /// Directional friction and springiness of a wheel's contact with the floor.
  void ApplyWheelContact(const GeomTag& wheel, bool wheel_first, dContact* contact) const;

  dWorldID world_ = nullptr;
  dSpaceID space_ = nullptr;
  dJointGroupID contact_group_ = nullptr;
  double step_s_ = 0.002;  ///< of the step being taken (sprung contacts need it)
  std::deque<GeomTag> tags_;
  std::vector<ContactEvent> contacts_;
  std::vector<dGeomID> statics_;
  GeomTag* static_tag_ = nullptr;
  uint64_t rng_state_;
};

}  // namespace fleetnav::sim
