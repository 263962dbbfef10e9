#pragma once

#include <ode/ode.h>

#include <Eigen/Core>
#include <array>
#include <string>

#include "fleetnav/core/pose2.hpp"
#include "fleetnav/sim/geometry2d.hpp"
#include "fleetnav/sim/ode_world.hpp"
#include "fleetnav/sim/world_description.hpp"

namespace fleetnav::sim {

/// A shopping trolley in ODE (KUKA thesis ch. 15): a 15 kg body standing on four legs of the
/// world file's size, each leg a capsule down to the floor on a swivel caster (low floor
/// friction: it rolls away when pushed rather than sliding stiffly). Robots collide with the
/// legs — a physical robot that drives into one pushes the trolley along, a kinematic one stops
/// — and drive under the basket between them. A robot's lift latches it (Latch: raised by
/// kLiftHeightM and held by a fixed joint to the robot's chassis, its legs off the floor, its
/// contacts the carrier's) until Release sets it down where it is. Not thread-safe; owned by
/// the simulation.
class TrolleyBody {
 public:
  static constexpr double kMassKg = 15.0;
  static constexpr double kLegHeightM = 1.0;
  /// Floor friction of a leg's caster.
  static constexpr double kCasterMu = 0.05;
  /// How far a lift raises a latched trolley: its casters clear the floor.
  static constexpr double kLiftHeightM = 0.02;

  TrolleyBody(OdeWorld* world, int trolley_index, const Trolley& trolley);
  ~TrolleyBody();
  TrolleyBody(const TrolleyBody&) = delete;
  TrolleyBody& operator=(const TrolleyBody&) = delete;

  const std::string& id() const { return id_; }
  Pose2 pose() const;
  /// The legs where they stand now, as the sensors and the kinematic robots see them.
  std::array<Shape2, 4> LegShapes() const;
  /// Outer size: length along its x axis, width along y.
  const Eigen::Vector2d& size_m() const { return size_m_; }

  /// Raises the trolley onto `carrier` (the chassis of robot `robot_index`) and holds it there.
  void Latch(dBodyID carrier, int robot_index);
  /// Sets a latched trolley down where it is, at rest.
  void Release();
  /// The robot carrying it, or -1.
  int carrier_robot_index() const { return tag_->carrier_robot_index; }

 private:
  OdeWorld* world_ = nullptr;
  GeomTag* tag_ = nullptr;
  dJointID latch_ = nullptr;
  Eigen::Vector2d size_m_;
  std::string id_;
  double leg_radius_m_ = 0.0;
  std::array<Eigen::Vector2d, 4> legs_in_trolley_{};
  dBodyID body_ = nullptr;
};

}  // namespace fleetnav::sim
