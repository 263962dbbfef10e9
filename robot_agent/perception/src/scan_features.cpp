#include "fleetnav/robot_agent/scan_features.hpp"

#include <algorithm>
#include <cmath>

namespace fleetnav::agent {

std::vector<Eigen::Vector2d> ScanPoints(const LaserScanSample& scan, const Pose2& laser_in_base) {
  std::vector<Eigen::Vector2d> points;
  for (size_t i = 0; i < scan.ranges_m.size(); ++i) {
    const double r = scan.ranges_m[i];
    if (!std::isfinite(r) || r <= 0.0 || r >= scan.range_max_m) continue;
    const double a = scan.angle_min_rad + static_cast<double>(i) * scan.angle_increment_rad;
    points.push_back(laser_in_base.TransformPoint({r * std::cos(a), r * std::sin(a)}));
  }
  return points;
}

std::vector<std::vector<Eigen::Vector2d>> ClusterPoints(const std::vector<Eigen::Vector2d>& points,
                                                        double max_gap_m) {
  std::vector<std::vector<Eigen::Vector2d>> clusters;
  for (size_t i = 0; i < points.size(); ++i) {
    if (i == 0 || (points[i] - points[i - 1]).norm() > max_gap_m) clusters.emplace_back();
    clusters.back().push_back(points[i]);
  }
  return clusters;
}

namespace {

double DistanceToLine(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                      const Eigen::Vector2d& b) {
  const Eigen::Vector2d d = b - a;
  const double length = d.norm();
  if (length < 1e-12) return (p - a).norm();
  return std::abs(d.x() * (p.y() - a.y()) - d.y() * (p.x() - a.x())) / length;
}

void Split(const std::vector<Eigen::Vector2d>& points, size_t first, size_t last,
           double split_distance_m, std::vector<LineSegment>* out) {
  double worst = 0.0;
  size_t at = first;
  for (size_t i = first + 1; i < last; ++i) {
    const double d = DistanceToLine(points[i], points[first], points[last]);
    if (d > worst) {
      worst = d;
      at = i;
    }
  }
  if (worst > split_distance_m) {
    Split(points, first, at, split_distance_m, out);
    Split(points, at, last, split_distance_m, out);
  } else {
    out->push_back({points[first], points[last]});
  }
}

}  // namespace

std::vector<LineSegment> IterativeEndPointFit(const std::vector<Eigen::Vector2d>& cluster,
                                              double split_distance_m, double merge_angle_rad) {
  std::vector<LineSegment> split;
  if (cluster.empty()) return split;
  if (cluster.size() == 1) return {{cluster[0], cluster[0]}};
  Split(cluster, 0, cluster.size() - 1, split_distance_m, &split);
  std::vector<LineSegment> merged{split.front()};
  for (size_t i = 1; i < split.size(); ++i) {
    LineSegment& last = merged.back();
    const Eigen::Vector2d a = last.to - last.from, b = split[i].to - split[i].from;
    const double angle = std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0));
    if (a.norm() > 1e-9 && b.norm() > 1e-9 && angle < merge_angle_rad) {
      last.to = split[i].to;
    } else {
      merged.push_back(split[i]);
    }
  }
  return merged;
}

std::optional<Circle> FitCircleOfRadius(const std::vector<Eigen::Vector2d>& cluster,
                                        double radius_m, const Eigen::Vector2d& viewpoint) {
  if (cluster.empty()) return std::nullopt;
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : cluster) centroid += p;
  centroid /= static_cast<double>(cluster.size());
  const Eigen::Vector2d away = (centroid - viewpoint).normalized();
  Eigen::Vector2d c = centroid + radius_m * away;
  // Gauss–Newton on sum (|p - c| - r)²; a cluster of one or two points keeps the start.
  for (int iteration = 0; iteration < 10 && cluster.size() >= 3; ++iteration) {
    Eigen::Matrix2d jtj = Eigen::Matrix2d::Zero();
    Eigen::Vector2d jtr = Eigen::Vector2d::Zero();
    for (const Eigen::Vector2d& p : cluster) {
      const Eigen::Vector2d d = c - p;
      const double n = d.norm();
      if (n < 1e-9) continue;
      const Eigen::Vector2d j = d / n;
      jtj += j * j.transpose();
      jtr += j * (n - radius_m);
    }
    if (std::abs(jtj.determinant()) < 1e-12) break;
    const Eigen::Vector2d step = jtj.ldlt().solve(jtr);
    c -= step;
    if (step.norm() < 1e-6) break;
  }
  // A fit that wandered off (few, noisy points) falls back to the start.
  if ((c - centroid).norm() > 2.0 * radius_m) c = centroid + radius_m * away;
  double sum = 0.0;
  for (const Eigen::Vector2d& p : cluster) sum += std::pow((p - c).norm() - radius_m, 2);
  return Circle{c, radius_m, std::sqrt(sum / static_cast<double>(cluster.size()))};
}

}  // namespace fleetnav::agent
