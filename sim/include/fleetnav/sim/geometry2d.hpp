#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "fleetnav/core/pose2.hpp"

namespace fleetnav::sim {

/// A solid as the sensors see it in the floor plane: a convex polygon (counter-clockwise) or a
/// circle, standing from the floor up to height_m. owner is -1 for the world's static
/// obstacles and the robot's index for a robot footprint. Value type.
struct Shape2 {
  enum class Kind : uint8_t { kPolygon, kCircle };
  Kind kind = Kind::kPolygon;
  std::vector<Eigen::Vector2d> vertices;  ///< polygon only
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  double radius = 0.0;  ///< circle radius, or the polygon's bounding radius about center
  double height_m = 1.0;
  int owner = -1;
};

/// The first hit of a ray on a shape: distance along the (unit) ray direction and the surface
/// normal there (pointing out of the shape).
struct RayHit {
  double distance_m = 0.0;
  Eigen::Vector2d normal = Eigen::Vector2d::UnitX();
};

/// A convex polygon shape with its bounding circle filled in.
Shape2 PolygonShape(std::vector<Eigen::Vector2d> vertices, double height_m, int owner);
Shape2 CircleShape(const Eigen::Vector2d& center, double radius_m, double height_m, int owner);
/// An oriented rectangle (centre, full size along its own axes, yaw).
Shape2 BoxShape(const Eigen::Vector2d& center, const Eigen::Vector2d& size, double yaw_rad,
                double height_m, int owner);
/// A robot footprint (base_link polygon) placed at `pose`, grown outwards by `inflate_m`
/// (about its bounding centre; exact for rectangles).
Shape2 FootprintShape(const std::vector<Eigen::Vector2d>& footprint, const Pose2& pose,
                      double height_m, int owner, double inflate_m = 0.0);

/// First intersection of the ray origin + t·direction (direction unit length, 0 ≤ t ≤ max_m)
/// with the shape's boundary; nullopt for no hit. A ray starting inside a shape hits its
/// boundary from within.
std::optional<RayHit> CastRay(const Shape2& shape, const Eigen::Vector2d& origin,
                              const Eigen::Vector2d& direction, double max_m);

/// Whether two shapes overlap (separating-axis test; circles by closest point).
bool Overlap(const Shape2& a, const Shape2& b);

/// The smallest distance between two convex polygons' boundaries; 0 when they overlap.
double PolygonDistance(const Shape2& a, const Shape2& b);

/// Whether a point lies inside a shape.
bool Contains(const Shape2& shape, const Eigen::Vector2d& point);

/// The parameter interval [t0, t1] ⊂ [0, 1] of the segment a→b inside the axis-aligned
/// rectangle [lo, hi] (Liang–Barsky); nullopt when the segment misses it.
std::optional<std::pair<double, double>> ClipSegment(const Eigen::Vector2d& a,
                                                     const Eigen::Vector2d& b,
                                                     const Eigen::Vector2d& lo,
                                                     const Eigen::Vector2d& hi);

/// Whether p lies on the strip of half-width half_width_m around segment a→b (a rectangle, no
/// round caps).
bool OnSegmentStrip(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double half_width_m,
                    const Eigen::Vector2d& p);

}  // namespace fleetnav::sim
