#include "fleetnav/robot_agent/control/common/stripe_path.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include "fleetnav/core/angles.hpp"

namespace fleetnav::agent {
namespace {

constexpr double kJoinM = 0.02;  ///< piece ends closer than this are one joint

struct Edge {
  int a = 0;
  int b = 0;
  int stripe_id = 0;
};

/// The vertices of `edges` in path order, or nullopt unless they form one simple open path.
std::optional<std::vector<int>> Walk(const std::vector<Edge>& edges) {
  std::map<int, std::vector<int>> adjacent;  // vertex -> edge indices
  for (size_t e = 0; e < edges.size(); ++e) {
    adjacent[edges[e].a].push_back(static_cast<int>(e));
    adjacent[edges[e].b].push_back(static_cast<int>(e));
  }
  int start = -1;
  for (const auto& [vertex, incident] : adjacent) {
    if (incident.size() > 2) return std::nullopt;
    if (incident.size() == 1 && start < 0) start = vertex;
  }
  if (start < 0) return std::nullopt;  // a closed loop
  std::vector<int> order{start};
  std::vector<bool> used(edges.size(), false);
  int at = start;
  while (true) {
    int next = -1;
    for (int e : adjacent[at]) {
      if (used[static_cast<size_t>(e)]) continue;
      used[static_cast<size_t>(e)] = true;
      next = edges[static_cast<size_t>(e)].a == at ? edges[static_cast<size_t>(e)].b
                                                   : edges[static_cast<size_t>(e)].a;
      break;
    }
    if (next < 0) break;
    order.push_back(next);
    at = next;
  }
  if (order.size() != edges.size() + 1) return std::nullopt;  // not connected
  return order;
}

}  // namespace

std::optional<StripePath> StripePath::Build(const std::vector<StripeMarker>& pieces,
                                            int stripe_id) {
  std::vector<Eigen::Vector2d> joints;
  const auto joint = [&](const Eigen::Vector2d& p) {
    for (size_t i = 0; i < joints.size(); ++i) {
      if ((joints[i] - p).norm() < kJoinM) return static_cast<int>(i);
    }
    joints.push_back(p);
    return static_cast<int>(joints.size() - 1);
  };
  std::vector<Edge> edges;
  for (const StripeMarker& piece : pieces) {
    const Eigen::Vector2d half =
        0.5 * piece.length_m * Eigen::Vector2d(std::cos(piece.yaw_rad), std::sin(piece.yaw_rad));
    const int a = joint(piece.position_m - half);
    const int b = joint(piece.position_m + half);
    if (a != b) edges.push_back({a, b, piece.stripe_id});
  }
  // The connected part of the pieces that holds the leg's stripe.
  std::set<int> reached;
  for (const Edge& e : edges) {
    if (e.stripe_id == stripe_id) reached.insert({e.a, e.b});
  }
  if (reached.empty()) return std::nullopt;
  for (bool grew = true; grew;) {
    grew = false;
    for (const Edge& e : edges) {
      if (reached.count(e.a) != reached.count(e.b)) {
        reached.insert({e.a, e.b});
        grew = true;
      }
    }
  }
  std::vector<Edge> joined;
  std::vector<Edge> own;
  for (const Edge& e : edges) {
    if (reached.count(e.a) > 0) joined.push_back(e);
    if (e.stripe_id == stripe_id) own.push_back(e);
  }
  std::optional<std::vector<int>> order = Walk(joined);
  if (!order) order = Walk(own);
  if (!order) return std::nullopt;
  std::vector<Eigen::Vector2d> vertices;
  for (int v : *order) vertices.push_back(joints[static_cast<size_t>(v)]);
  return StripePath(std::move(vertices));
}

StripePath::StripePath(std::vector<Eigen::Vector2d> vertices) : vertices_(std::move(vertices)) {
  Measure();
}

void StripePath::Measure() {
  const size_t segments = vertices_.size() - 1;
  cumulative_m_.assign(vertices_.size(), 0.0);
  for (size_t i = 0; i < segments; ++i) {
    cumulative_m_[i + 1] = cumulative_m_[i] + (vertices_[i + 1] - vertices_[i]).norm();
  }
  // The turn at each inner vertex is shared by the two segments that meet there.
  std::vector<double> turn_rad(vertices_.size(), 0.0);
  for (size_t v = 1; v + 1 < vertices_.size(); ++v) {
    const Eigen::Vector2d in = vertices_[v] - vertices_[v - 1];
    const Eigen::Vector2d out = vertices_[v + 1] - vertices_[v];
    turn_rad[v] = NormalizeAngle(std::atan2(out.y(), out.x()) - std::atan2(in.y(), in.x()));
  }
  curvature_per_m_.assign(segments, 0.0);
  for (size_t i = 0; i < segments; ++i) {
    const double length_m = cumulative_m_[i + 1] - cumulative_m_[i];
    curvature_per_m_[i] = 0.5 * (turn_rad[i] + turn_rad[i + 1]) / std::max(length_m, 1e-6);
  }
}

StripePath::Foot StripePath::FootOnSegment(size_t segment, const Eigen::Vector2d& point) const {
  const Eigen::Vector2d& a = vertices_[segment];
  const Eigen::Vector2d d = vertices_[segment + 1] - a;
  const double length_m = d.norm();
  Foot foot;
  foot.tangent = length_m > 1e-9 ? Eigen::Vector2d(d / length_m) : Eigen::Vector2d::UnitX();
  const double along = std::clamp((point - a).dot(foot.tangent), 0.0, length_m);
  foot.point = a + along * foot.tangent;
  foot.s_m = cumulative_m_[segment] + along;
  foot.curvature_per_m = curvature_per_m_[segment];
  foot.distance_m = (point - foot.point).norm();
  return foot;
}

StripePath::Foot StripePath::Project(const Eigen::Vector2d& point, double window_m) {
  Foot best;
  best.distance_m = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i + 1 < vertices_.size(); ++i) {
    if (last_s_m_ && (cumulative_m_[i + 1] < *last_s_m_ - window_m ||
                      cumulative_m_[i] > *last_s_m_ + window_m)) {
      continue;
    }
    const Foot foot = FootOnSegment(i, point);
    if (foot.distance_m < best.distance_m) best = foot;
  }
  if (!std::isfinite(best.distance_m)) {  // the window held nothing: search everywhere
    last_s_m_.reset();
    return Project(point, window_m);
  }
  last_s_m_ = best.s_m;
  return best;
}

void StripePath::OrientAlong(const Eigen::Vector2d& point, const Eigen::Vector2d& heading) {
  last_s_m_.reset();
  const Foot foot = Project(point);
  if (foot.tangent.dot(heading) < 0.0) {
    std::reverse(vertices_.begin(), vertices_.end());
    Measure();
    last_s_m_ = length_m() - foot.s_m;
  }
}

double StripePath::MaxCurvatureAhead(double s_m, double ahead_m) const {
  double most = 0.0;
  for (size_t i = 0; i + 1 < vertices_.size(); ++i) {
    if (cumulative_m_[i + 1] < s_m || cumulative_m_[i] > s_m + ahead_m) continue;
    most = std::max(most, std::abs(curvature_per_m_[i]));
  }
  return most;
}

}  // namespace fleetnav::agent
