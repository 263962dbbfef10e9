#include "fleetnav/sim/geometry2d.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "fleetnav/core/segment_distance.hpp"

namespace fleetnav::sim {
namespace {

double Cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// Projection interval of a shape on an axis.
std::pair<double, double> Project(const Shape2& shape, const Eigen::Vector2d& axis) {
  if (shape.kind == Shape2::Kind::kCircle) {
    const double c = shape.center.dot(axis);
    return {c - shape.radius, c + shape.radius};
  }
  double lo = std::numeric_limits<double>::infinity();
  double hi = -lo;
  for (const Eigen::Vector2d& v : shape.vertices) {
    const double d = v.dot(axis);
    lo = std::min(lo, d);
    hi = std::max(hi, d);
  }
  return {lo, hi};
}

bool SeparatedOn(const Shape2& a, const Shape2& b, const Eigen::Vector2d& axis) {
  const auto [a_lo, a_hi] = Project(a, axis);
  const auto [b_lo, b_hi] = Project(b, axis);
  return a_hi < b_lo || b_hi < a_lo;
}

// Axes to test for a polygon: its edge normals.
bool SeparatedByEdges(const Shape2& polygon, const Shape2& other) {
  const size_t n = polygon.vertices.size();
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d edge = polygon.vertices[(i + 1) % n] - polygon.vertices[i];
    const Eigen::Vector2d axis = Eigen::Vector2d(edge.y(), -edge.x()).normalized();
    if (SeparatedOn(polygon, other, axis)) return true;
  }
  return false;
}

/// The smallest distance from any vertex of `from` to any edge of `to`.
double VertexToEdgeDistance(const Shape2& from, const Shape2& to) {
  double best = std::numeric_limits<double>::infinity();
  const size_t n = to.vertices.size();
  for (const Eigen::Vector2d& v : from.vertices) {
    for (size_t i = 0; i < n; ++i) {
      best = std::min(best, PointSegmentDistance(v, to.vertices[i], to.vertices[(i + 1) % n]));
    }
  }
  return best;
}

}  // namespace

Shape2 PolygonShape(std::vector<Eigen::Vector2d> vertices, double height_m, int owner) {
  Shape2 shape;
  shape.kind = Shape2::Kind::kPolygon;
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& v : vertices) center += v;
  center /= static_cast<double>(std::max<size_t>(1, vertices.size()));
  double radius = 0.0;
  for (const Eigen::Vector2d& v : vertices) radius = std::max(radius, (v - center).norm());
  shape.vertices = std::move(vertices);
  shape.center = center;
  shape.radius = radius;
  shape.height_m = height_m;
  shape.owner = owner;
  return shape;
}

Shape2 CircleShape(const Eigen::Vector2d& center, double radius_m, double height_m, int owner) {
  Shape2 shape;
  shape.kind = Shape2::Kind::kCircle;
  shape.center = center;
  shape.radius = radius_m;
  shape.height_m = height_m;
  shape.owner = owner;
  return shape;
}

Shape2 BoxShape(const Eigen::Vector2d& center, const Eigen::Vector2d& size, double yaw_rad,
                double height_m, int owner) {
  const double c = std::cos(yaw_rad), s = std::sin(yaw_rad);
  const Eigen::Vector2d ax(c * 0.5 * size.x(), s * 0.5 * size.x());
  const Eigen::Vector2d ay(-s * 0.5 * size.y(), c * 0.5 * size.y());
  return PolygonShape({center - ax - ay, center + ax - ay, center + ax + ay, center - ax + ay},
                      height_m, owner);
}

Shape2 FootprintShape(const std::vector<Eigen::Vector2d>& footprint, const Pose2& pose,
                      double height_m, int owner, double inflate_m) {
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& v : footprint) center += v;
  center /= static_cast<double>(std::max<size_t>(1, footprint.size()));
  std::vector<Eigen::Vector2d> placed;
  placed.reserve(footprint.size());
  for (const Eigen::Vector2d& v : footprint) {
    Eigen::Vector2d local = v;
    if (inflate_m != 0.0) {
      const Eigen::Vector2d d = v - center;
      local = v + Eigen::Vector2d(d.x() >= 0 ? inflate_m : -inflate_m,
                                  d.y() >= 0 ? inflate_m : -inflate_m);
    }
    placed.push_back(pose.TransformPoint(local));
  }
  return PolygonShape(std::move(placed), height_m, owner);
}

std::optional<RayHit> CastRay(const Shape2& shape, const Eigen::Vector2d& origin,
                              const Eigen::Vector2d& direction, double max_m) {
  if (shape.kind == Shape2::Kind::kCircle) {
    const Eigen::Vector2d m = origin - shape.center;
    const double b = m.dot(direction);
    const double c = m.squaredNorm() - shape.radius * shape.radius;
    const double disc = b * b - c;
    if (disc < 0.0) return std::nullopt;
    const double root = std::sqrt(disc);
    double t = -b - root;
    if (t < 0.0) t = -b + root;  // origin inside the circle
    if (t < 0.0 || t > max_m) return std::nullopt;
    const Eigen::Vector2d point = origin + t * direction;
    return RayHit{t, (point - shape.center).normalized()};
  }
  // Bounding-circle rejection first: most rays miss most shapes.
  const Eigen::Vector2d m = origin - shape.center;
  const double b = m.dot(direction);
  const double c = m.squaredNorm() - shape.radius * shape.radius;
  if (c > 0.0 && (b > 0.0 || b * b < c)) return std::nullopt;
  double best = std::numeric_limits<double>::infinity();
  Eigen::Vector2d best_normal = Eigen::Vector2d::UnitX();
  const size_t n = shape.vertices.size();
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d& p = shape.vertices[i];
    const Eigen::Vector2d edge = shape.vertices[(i + 1) % n] - p;
    const double denom = Cross(direction, edge);
    if (std::abs(denom) < 1e-12) continue;
    const Eigen::Vector2d w = p - origin;
    const double t = Cross(w, edge) / denom;
    const double u = Cross(w, direction) / denom;
    if (t >= 0.0 && t <= max_m && u >= 0.0 && u <= 1.0 && t < best) {
      best = t;
      best_normal = Eigen::Vector2d(edge.y(), -edge.x()).normalized();  // outward for CCW
    }
  }
  if (!std::isfinite(best)) return std::nullopt;
  return RayHit{best, best_normal};
}

bool Overlap(const Shape2& a, const Shape2& b) {
  if ((a.center - b.center).norm() > a.radius + b.radius) return false;
  if (a.kind == Shape2::Kind::kCircle && b.kind == Shape2::Kind::kCircle) return true;
  if (a.kind == Shape2::Kind::kCircle) return Overlap(b, a);
  if (SeparatedByEdges(a, b)) return false;
  if (b.kind == Shape2::Kind::kPolygon) return !SeparatedByEdges(b, a);
  // Polygon against circle: also the axis from the circle centre to the nearest vertex.
  Eigen::Vector2d nearest = a.vertices.front();
  for (const Eigen::Vector2d& v : a.vertices) {
    if ((v - b.center).squaredNorm() < (nearest - b.center).squaredNorm()) nearest = v;
  }
  const Eigen::Vector2d axis = nearest - b.center;
  if (axis.norm() < 1e-12) return true;
  return !SeparatedOn(a, b, axis.normalized());
}

double PolygonDistance(const Shape2& a, const Shape2& b) {
  if (Overlap(a, b)) return 0.0;
  // Between disjoint convex polygons the closest pair always has a vertex on one side.
  return std::min(VertexToEdgeDistance(a, b), VertexToEdgeDistance(b, a));
}

bool Contains(const Shape2& shape, const Eigen::Vector2d& point) {
  if (shape.kind == Shape2::Kind::kCircle) {
    return (point - shape.center).squaredNorm() <= shape.radius * shape.radius;
  }
  const size_t n = shape.vertices.size();
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d edge = shape.vertices[(i + 1) % n] - shape.vertices[i];
    if (Cross(edge, point - shape.vertices[i]) < 0.0) return false;
  }
  return true;
}

std::optional<std::pair<double, double>> ClipSegment(const Eigen::Vector2d& a,
                                                     const Eigen::Vector2d& b,
                                                     const Eigen::Vector2d& lo,
                                                     const Eigen::Vector2d& hi) {
  double t0 = 0.0, t1 = 1.0;
  const Eigen::Vector2d d = b - a;
  for (int axis = 0; axis < 2; ++axis) {
    const double p[2] = {-d[axis], d[axis]};
    const double q[2] = {a[axis] - lo[axis], hi[axis] - a[axis]};
    for (int k = 0; k < 2; ++k) {
      if (std::abs(p[k]) < 1e-15) {
        if (q[k] < 0.0) return std::nullopt;
        continue;
      }
      const double r = q[k] / p[k];
      if (p[k] < 0.0) {
        t0 = std::max(t0, r);
      } else {
        t1 = std::min(t1, r);
      }
    }
  }
  if (t0 > t1) return std::nullopt;
  return std::make_pair(t0, t1);
}

bool OnSegmentStrip(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double half_width_m,
                    const Eigen::Vector2d& p) {
  const Eigen::Vector2d d = b - a;
  const double length_sq = d.squaredNorm();
  if (length_sq < 1e-18) return false;
  const double t = (p - a).dot(d) / length_sq;
  if (t < 0.0 || t > 1.0) return false;
  return std::abs(Cross(d, p - a)) / std::sqrt(length_sq) <= half_width_m;
}

}  // namespace fleetnav::sim
