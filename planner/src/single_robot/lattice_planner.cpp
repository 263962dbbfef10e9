#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <queue>

#include "absl/container/flat_hash_map.h"
#include "absl/strings/str_cat.h"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/planner/grid/body_clearance.hpp"
#include "fleetnav/planner/single_robot/single_robot_planner.hpp"
#include "shortest_curve_internal.hpp"

namespace fleetnav::planner {
namespace {

/// The expansion budget of the platforms' and cars' lattices: it, not the request's wall-time
/// limit, ends a search that finds no way, so that a run replays the same on a busy machine
/// (a 16 m way round a store's shelf rows took 1.3 M expansions, 2.2 s on these cores).
constexpr int kNavigationExpansions = 3'000'000;

/// A start deeper than this in collision (BodyClearance below minus this) is not backed out of:
/// that is a wrong pose, not a touch. BodyClearance's discs reach up to 0.19 m past the delivery
/// robot's nose and tail, so a car touching a box head-on measures about -0.19 m.
constexpr double kEscapableDepthM = 0.25;

/// A goal's place within LatticeParams::goal_place_tolerance_m is searched for while it costs at
/// most this much more than the first one within the request's tolerance (a coarse map's cells
/// may not allow it at all).
constexpr double kGoalPlaceSearchM = 1.0;

/// The Lely's side ultrasonics see 2.5 m (the agent's ultrasonic_range_max_m); they sit on its
/// centre line's sides, so an obstacle abeam within this distance of base_link is in reach.
constexpr double kLelyUltrasonicReachM = 2.5;

/// The heuristic's Dijkstra from the goal runs until it is this many times the start's
/// distance plus the margin away: weighted A* rarely strays further from the straight way.
constexpr double kHeuristicReachFactor = 2.0;
constexpr double kHeuristicReachMarginM = 3.0;

double AngleDiff(double a, double b) {
  double d = std::fmod(a - b, 2.0 * kPi);
  if (d > kPi) d -= 2.0 * kPi;
  if (d < -kPi) d += 2.0 * kPi;
  return d;
}

bool Positive(double v) { return v > 0.0 && std::isfinite(v); }

}  // namespace

absl::Status PathRequest::Validate() const {
  for (const Pose2* p : {&start, &goal}) {
    if (!std::isfinite(p->x_m()) || !std::isfinite(p->y_m()) || !std::isfinite(p->yaw_rad())) {
      return absl::InvalidArgumentError(p == &start ? "start: not finite" : "goal: not finite");
    }
  }
  if (!Positive(goal_tolerance_m))
    return absl::InvalidArgumentError("goal_tolerance_m: must be > 0");
  if (!Positive(goal_tolerance_rad)) {
    return absl::InvalidArgumentError("goal_tolerance_rad: must be > 0");
  }
  if (!Positive(time_limit_s)) return absl::InvalidArgumentError("time_limit_s: must be > 0");
  return absl::OkStatus();
}

absl::Status LatticeParams::Validate() const {
  if (heading_bins < 4 || heading_bins > 360) {
    return absl::InvalidArgumentError("heading_bins: must be in [4, 360]");
  }
  if (!(step_m >= 0.0) || !std::isfinite(step_m)) {
    return absl::InvalidArgumentError("step_m: must be finite and >= 0");
  }
  if (!(turn_cost_m_per_rad >= 0.0)) {
    return absl::InvalidArgumentError("turn_cost_m_per_rad: must be >= 0");
  }
  if (!(reverse_cost_factor >= 1.0)) {
    return absl::InvalidArgumentError("reverse_cost_factor: must be >= 1");
  }
  if (!(direction_switch_cost_m >= 0.0) || !std::isfinite(direction_switch_cost_m)) {
    return absl::InvalidArgumentError("direction_switch_cost_m: must be finite and >= 0");
  }
  if (!(heuristic_weight >= 1.0))
    return absl::InvalidArgumentError("heuristic_weight: must be >= 1");
  if (max_expansions <= 0) return absl::InvalidArgumentError("max_expansions: must be > 0");
  if (!(clearance_weight >= 0.0) || !std::isfinite(clearance_weight)) {
    return absl::InvalidArgumentError("clearance_weight: must be finite and >= 0");
  }
  if (!Positive(preferred_clearance_m)) {
    return absl::InvalidArgumentError("preferred_clearance_m: must be > 0");
  }
  if (!(coastal_weight >= 0.0) || !std::isfinite(coastal_weight)) {
    return absl::InvalidArgumentError("coastal_weight: must be finite and >= 0");
  }
  if (!Positive(coast_reach_m)) return absl::InvalidArgumentError("coast_reach_m: must be > 0");
  if (!(goal_place_tolerance_m >= 0.0) || !std::isfinite(goal_place_tolerance_m)) {
    return absl::InvalidArgumentError("goal_place_tolerance_m: must be finite and >= 0");
  }
  if (analytic_every < 0) return absl::InvalidArgumentError("analytic_every: must be >= 0");
  if (!(escape_m >= 0.0) || !std::isfinite(escape_m)) {
    return absl::InvalidArgumentError("escape_m: must be finite and >= 0");
  }
  if (!(turning_radius_factor >= 1.0) || !std::isfinite(turning_radius_factor)) {
    return absl::InvalidArgumentError("turning_radius_factor: must be finite and >= 1");
  }
  if (!Positive(analytic_range_m)) {
    return absl::InvalidArgumentError("analytic_range_m: must be > 0");
  }
  if (!(analytic_min_clearance_m >= 0.0) || !std::isfinite(analytic_min_clearance_m)) {
    return absl::InvalidArgumentError("analytic_min_clearance_m: must be finite and >= 0");
  }
  return absl::OkStatus();
}

namespace {

/// What every navigation preset shares: clearance costs (w 4, c* 0.45 m) and the expansion
/// budget that ends a fruitless search before any wall-time limit does.
LatticeParams NavigationLatticeParams() {
  LatticeParams p;
  p.clearance_weight = 4.0;
  p.preferred_clearance_m = 0.45;
  p.max_expansions = kNavigationExpansions;
  return p;
}

}  // namespace

LatticeParams DifferentialLatticeParams() {
  LatticeParams p = NavigationLatticeParams();
  p.coastal_weight = 1.0;
  p.coast_reach_m = kLelyUltrasonicReachM;
  // Plain A*: with the coastal costs in its heuristic the search stays small (under 10,000
  // expansions across a generated barn), where a weighted one (1.5) wandered: 21 m over open
  // floor for a 17 m way along a fence.
  p.heuristic_weight = 1.0;
  p.goal_place_tolerance_m = 0.05;
  return p;
}

LatticeParams PlatformLatticeParams() {
  LatticeParams p = NavigationLatticeParams();
  p.escape_m = 1.0;
  return p;
}

LatticeParams CarLatticeParams() {
  LatticeParams p = PlatformLatticeParams();
  p.heading_bins = 32;
  p.analytic_every = 8;
  p.turning_radius_factor = 1.3;
  p.direction_switch_cost_m = 3.0;
  return p;
}

LatticePlanner::LatticePlanner(Costmap* costmap, const RobotModel& model,
                               const LatticeParams& params)
    : costmap_(costmap), model_(model), params_(params) {
  const double res = costmap_->resolution_m();
  const double bin = 2.0 * kPi / params_.heading_bins;
  const double step = params_.step_m > 0 ? params_.step_m : 1.5 * res;
  const bool reverse = model_.limits.max_reverse_speed_mps > 0.0;
  const double turn = params_.turn_cost_m_per_rad * bin;
  switch (model_.kinematics) {
    case Kinematics::kDifferential:
      primitives_ = {{step, 0, 0, step}, {0, 0, bin, turn}, {0, 0, -bin, turn}};
      if (reverse) primitives_.push_back({-step, 0, 0, step * params_.reverse_cost_factor});
      break;
    case Kinematics::kOmnidirectional:
      for (int dx = -1; dx <= 1; ++dx) {
        for (int dy = -1; dy <= 1; ++dy) {
          if (dx == 0 && dy == 0) continue;
          const double len = step * std::hypot(dx, dy);
          primitives_.push_back({step * dx, step * dy, 0, len});
        }
      }
      primitives_.push_back({0, 0, bin, turn});
      primitives_.push_back({0, 0, -bin, turn});
      break;
    case Kinematics::kAckermann: {
      turning_radius_m_ = params_.turning_radius_factor * model_.wheelbase_m /
                          std::tan(model_.limits.max_steering_rad);
      const double arc = std::max(turning_radius_m_ * bin, step);
      const double dyaw = arc / turning_radius_m_;
      for (double dir : {1.0, -1.0}) {
        if (dir < 0 && !reverse) continue;
        const double cost = arc * (dir > 0 ? 1.0 : params_.reverse_cost_factor);
        primitives_.push_back({dir * arc, 0, 0, cost});
        primitives_.push_back({dir * arc, 0, dir * dyaw, cost * 1.05});
        primitives_.push_back({dir * arc, 0, -dir * dyaw, cost * 1.05});
      }
      break;
    }
  }
  // The largest disc round base_link inside the footprint (a convex polygon round it).
  base_room_m_ = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < model_.footprint_m.size(); ++i) {
    const Eigen::Vector2d a = model_.footprint_m[i];
    const Eigen::Vector2d b = model_.footprint_m[(i + 1) % model_.footprint_m.size()];
    const Eigen::Vector2d edge = b - a;
    const double t = std::clamp(-a.dot(edge) / std::max(edge.squaredNorm(), 1e-12), 0.0, 1.0);
    base_room_m_ = std::min(base_room_m_, (a + t * edge).norm());
  }
  if (!std::isfinite(base_room_m_)) base_room_m_ = 0.0;
  if (params_.clearance_weight > 0.0 || params_.escape_m > 0.0 ||
      (params_.analytic_every > 0 && model_.kinematics == Kinematics::kAckermann)) {
    clearance_ = std::make_shared<BodyClearance>(costmap_, model_.footprint_m);
  }
}

double LatticePlanner::ClearanceFactor(double clearance_m) const {
  const double short_by = params_.preferred_clearance_m - clearance_m;
  if (params_.clearance_weight <= 0.0 || short_by <= 0.0) return 1.0;
  const double share = std::min(short_by / params_.preferred_clearance_m, 1.0);
  return 1.0 + params_.clearance_weight * share * share;
}

LatticePlanner::Primitive LatticePlanner::OntoHeadingBins(double yaw_rad,
                                                          const Primitive& p) const {
  if (p.forward_m != 0.0 || p.lateral_m != 0.0 || p.dyaw_rad == 0.0) return p;
  const double bin = 2.0 * kPi / params_.heading_bins;
  const double in_bins = yaw_rad / bin;
  // The next bin's centre that way, a whole bin on from a centre (within rounding).
  const double target = p.dyaw_rad > 0.0 ? (std::floor(in_bins + 1e-6) + 1.0) * bin
                                         : (std::ceil(in_bins - 1e-6) - 1.0) * bin;
  const double dyaw = target - yaw_rad;
  return {0.0, 0.0, dyaw, params_.turn_cost_m_per_rad * std::abs(dyaw)};
}

double LatticePlanner::CoastExtra(double obstacle_distance_m) const {
  const double beyond_m = obstacle_distance_m - params_.coast_reach_m;
  if (params_.coastal_weight <= 0.0 || beyond_m <= 0.0) return 0.0;
  return params_.coastal_weight * std::min(beyond_m, 1.0);
}

std::vector<Pose2> LatticePlanner::AnalyticShot(const Pose2& from, const Pose2& goal) {
  const double res = costmap_->resolution_m();
  std::vector<Pose2> poses = internal::ShortestCurvePoses(
      from, goal, turning_radius_m_, model_.limits.max_reverse_speed_mps > 0.0, 0.5 * res);
  const double least_m =
      std::min({params_.analytic_min_clearance_m, clearance_->At(from), clearance_->At(goal)});
  for (const Pose2& q : poses) {
    if (!costmap_->PoseFree(q.x_m(), q.y_m(), q.yaw_rad()) ||
        clearance_->At(q) < least_m - 0.5 * res) {
      return {};
    }
  }
  return poses;
}

Pose2 LatticePlanner::Apply(const Pose2& from, const Primitive& p, double f) {
  const double th = from.yaw_rad();
  const double s = p.forward_m * f;
  const double phi = p.dyaw_rad * f;
  if (p.lateral_m != 0.0 || std::abs(phi) < 1e-12) {
    const double lat = p.lateral_m * f;
    return Pose2(from.x_m() + s * std::cos(th) - lat * std::sin(th),
                 from.y_m() + s * std::sin(th) + lat * std::cos(th), th + phi);
  }
  if (p.forward_m == 0.0) return Pose2(from.x_m(), from.y_m(), th + phi);
  const double r = s / phi;  // signed radius of the arc
  return Pose2(from.x_m() + r * (std::sin(th + phi) - std::sin(th)),
               from.y_m() - r * (std::cos(th + phi) - std::cos(th)), th + phi);
}

bool LatticePlanner::SegmentFree(const Pose2& from, const Primitive& p) const {
  const double res = costmap_->resolution_m();
  const double span = std::hypot(p.forward_m, p.lateral_m) +
                      std::abs(p.dyaw_rad) * costmap_->circumscribed_radius_m();
  const int samples = std::max(1, static_cast<int>(std::ceil(span / (0.5 * res))));
  for (int k = 1; k <= samples; ++k) {
    const Pose2 q = Apply(from, p, static_cast<double>(k) / samples);
    if (!costmap_->PoseFree(q.x_m(), q.y_m(), q.yaw_rad())) return false;
  }
  return true;
}

absl::StatusOr<PathResult> LatticePlanner::Plan(const PathRequest& request, std::stop_token stop) {
  if (absl::Status s = params_.Validate(); !s.ok()) return s;
  if (absl::Status s = request.Validate(); !s.ok()) return s;
  using Clock = std::chrono::steady_clock;
  const Clock::time_point t0 = Clock::now();
  const double res = costmap_->resolution_m();
  const int w = costmap_->width(), h = costmap_->height();
  const int bins = params_.heading_bins;
  auto cell_of = [&](double x, double y, int* cx, int* cy) {
    *cx = static_cast<int>(std::floor(x / res));
    *cy = static_cast<int>(std::floor(y / res));
    return costmap_->InBounds(*cx, *cy);
  };
  int sx, sy, gx, gy;
  if (!cell_of(request.start.x_m(), request.start.y_m(), &sx, &sy)) {
    return absl::InvalidArgumentError("start: outside the map");
  }
  // A start within the padding, or touching (a robot that has just touched a box): with
  // escape_m the search first backs out, each step gaining clearance; deeper in, or without
  // it, the start is refused.
  const bool start_free =
      costmap_->PoseFree(request.start.x_m(), request.start.y_m(), request.start.yaw_rad());
  if (!start_free && (params_.escape_m <= 0.0 || clearance_ == nullptr ||
                      clearance_->At(request.start) < -kEscapableDepthM)) {
    return absl::InvalidArgumentError("start: outside the map or in collision");
  }
  if (!cell_of(request.goal.x_m(), request.goal.y_m(), &gx, &gy)) {
    return absl::InvalidArgumentError("goal: outside the map");
  }

  // Heuristic: 8-connected Dijkstra from the goal over the cells where the footprint fits at
  // some orientation (not only its inscribed circle: a gap between a trolley's legs that the
  // circle passes and the body does not at any yaw would draw the search in until its budget
  // ran out, 3 M expansions for a 31 m way round the shelves in a store), run
  // lazily (as LaCAM's distance tables): a query resumes the search only until its cell is
  // settled, so a short trip settles a disc about as large as the trip, not the whole map. It
  // never goes further than kHeuristicReach times the start's distance; cells beyond the
  // frontier are at least `frontier` away, which keeps the heuristic a lower bound.
  const size_t cells = static_cast<size_t>(w) * h;
  std::vector<float> hdist(cells, std::numeric_limits<float>::infinity());
  using Item = std::pair<float, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> hopen;
  float frontier = 0.0f;  // every cell with hdist <= frontier is settled
  float reach = std::numeric_limits<float>::infinity();
  const double need = std::max(0.0, costmap_->inscribed_radius_m() - res);
  hdist[static_cast<size_t>(gy) * w + gx] = 0.0f;
  hopen.push({0.0f, gy * w + gx});
  // Settles cells until `cell` is settled, the search is exhausted or has reached `reach`.
  auto settle = [&](size_t cell) {
    static constexpr int kDx[] = {1, -1, 0, 0, 1, 1, -1, -1};
    static constexpr int kDy[] = {0, 0, 1, -1, 1, -1, 1, -1};
    while (hdist[cell] > frontier && !hopen.empty()) {
      auto [d, c] = hopen.top();
      if (d > hdist[c]) {
        hopen.pop();
        continue;
      }
      if (d > reach) return;
      hopen.pop();
      frontier = d;
      const int cx = c % w, cy = c / w;
      for (int k = 0; k < 8; ++k) {
        const int nx = cx + kDx[k], ny = cy + kDy[k];
        if (!costmap_->InBounds(nx, ny) || costmap_->IsObstacle(nx, ny) ||
            costmap_->DistanceToObstacle_m(nx, ny) < need || !costmap_->AnyYawFree(nx, ny)) {
          continue;
        }
        // With clearance costs, the least factor the body can have with its base in this cell
        // (its clearance is at most the cell's distance less the base's own room in the body):
        // the heuristic stays a lower bound and steers the search round tight places as the
        // cost does.
        // Coastal costs depend on the cell alone, so they count in full.
        const double distance_m = costmap_->DistanceToObstacle_m(nx, ny);
        const double factor =
            (params_.clearance_weight > 0.0 ? ClearanceFactor(distance_m - base_room_m_) : 1.0) +
            CoastExtra(distance_m);
        const float nd = d + static_cast<float>(res * (k < 4 ? 1.0 : M_SQRT2) * factor);
        const size_t n = static_cast<size_t>(ny) * w + nx;
        if (nd < hdist[n]) {
          hdist[n] = nd;
          hopen.push({nd, static_cast<int>(n)});
        }
      }
    }
    if (hopen.empty()) frontier = std::numeric_limits<float>::infinity();
  };
  const size_t start_cell = static_cast<size_t>(sy) * w + sx;
  settle(start_cell);
  if (std::isfinite(hdist[start_cell])) {
    reach = static_cast<float>(kHeuristicReachFactor * hdist[start_cell] + kHeuristicReachMarginM);
  }
  auto heuristic = [&](const Pose2& p) -> double {
    int cx, cy;
    if (!cell_of(p.x_m(), p.y_m(), &cx, &cy)) return std::numeric_limits<double>::infinity();
    const size_t cell = static_cast<size_t>(cy) * w + cx;
    settle(cell);
    const float d = hdist[cell];
    const double euclid = std::hypot(p.x_m() - request.goal.x_m(), p.y_m() - request.goal.y_m());
    if (d <= frontier) return std::max<double>(d - res, euclid);  // settled: exact
    if (std::isfinite(frontier)) return std::max<double>(frontier - res, euclid);
    return euclid + 1e3;  // the search finished: no way from the goal to here
  };
  auto bin_of = [&](double yaw) {
    const double turns = yaw / (2.0 * kPi);
    return static_cast<int>(std::lround((turns - std::floor(turns)) * bins)) % bins;
  };

  struct Node {
    Pose2 pose;
    double g;
    int parent;
    double escaped_m = -1.0;  ///< ≥ 0: still backing out of collision, this far so far
    int direction = 0;        ///< of the motion that reached it: 1 forward, −1 reverse, 0 none
  };
  std::vector<Node> nodes;
  // Best cost per (cell, heading bin), only for the states the search met.
  absl::flat_hash_map<uint64_t, float> best;
  const auto state_of = [&](int x, int y, int bin) {
    return (static_cast<uint64_t>(y) * w + x) * bins + bin;
  };
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> open;
  nodes.push_back({request.start, 0.0, -1, start_free ? -1.0 : 0.0});
  best[state_of(sx, sy, bin_of(request.start.yaw_rad()))] = 0.0f;
  open.push({params_.heuristic_weight * heuristic(request.start), 0});
  const bool turns_in_place = model_.kinematics != Kinematics::kAckermann;
  const double goal_tolerance_m =
      params_.goal_place_tolerance_m > 0.0
          ? std::min(request.goal_tolerance_m, params_.goal_place_tolerance_m)
          : request.goal_tolerance_m;
  const bool analytic = params_.analytic_every > 0 && model_.kinematics == Kinematics::kAckermann;
  int closest = 0;
  double closest_h = heuristic(request.start);
  int goal_node = -1;
  // The first goal within the request's tolerance but not within goal_place_tolerance_m, and
  // its cost: taken when no closer one is found for kGoalPlaceSearchM more.
  int loose_goal = -1;
  double loose_goal_cost = 0.0;
  PathResult result;
  while (!open.empty()) {
    if ((result.expanded & 255) == 0) {
      if (stop.stop_requested()) return absl::CancelledError("lattice: stopped");
      if (std::chrono::duration<double>(Clock::now() - t0).count() > request.time_limit_s) break;
    }
    if (result.expanded >= params_.max_expansions) break;
    auto [f, id] = open.top();
    open.pop();
    if (loose_goal >= 0 && f > loose_goal_cost + kGoalPlaceSearchM) break;
    const Node cur = nodes[id];
    int cx, cy;
    cell_of(cur.pose.x_m(), cur.pose.y_m(), &cx, &cy);
    // Stale entry? best[] is float: compare with a tolerance above its rounding at ~100 m.
    if (cur.g > best.at(state_of(cx, cy, bin_of(cur.pose.yaw_rad()))) + 1e-3) continue;
    ++result.expanded;
    const double dist =
        std::hypot(cur.pose.x_m() - request.goal.x_m(), cur.pose.y_m() - request.goal.y_m());
    if (dist < closest_h) {
      closest_h = dist;
      closest = id;
    }
    const bool escaping = cur.escaped_m >= 0.0;
    const double cur_clearance_m = escaping ? clearance_->At(cur.pose) : 0.0;
    if (dist <= request.goal_tolerance_m && !escaping &&
        (dist <= goal_tolerance_m || loose_goal < 0)) {
      // At the goal: its yaw within tolerance, or turned onto in place where the sweep is free.
      int reached = -1;
      const double dyaw = AngleDiff(request.goal.yaw_rad(), cur.pose.yaw_rad());
      if (std::abs(dyaw) <= request.goal_tolerance_rad) {
        reached = id;
      } else if (turns_in_place) {
        const Primitive turn{0, 0, dyaw, params_.turn_cost_m_per_rad * std::abs(dyaw)};
        if (SegmentFree(cur.pose, turn)) {
          nodes.push_back({Apply(cur.pose, turn, 1.0), cur.g + turn.cost, id});
          reached = static_cast<int>(nodes.size()) - 1;
        }
      }
      if (reached >= 0 && dist <= goal_tolerance_m) {
        goal_node = reached;
        break;
      }
      if (reached >= 0) {
        loose_goal = reached;
        loose_goal_cost = nodes[reached].g;
      }
    }
    if (analytic && !escaping && dist <= params_.analytic_range_m &&
        result.expanded % params_.analytic_every == 1 % params_.analytic_every) {
      std::vector<Pose2> shot = AnalyticShot(cur.pose, request.goal);
      if (!shot.empty()) {
        int parent = id;
        for (const Pose2& q : shot) {
          nodes.push_back({q, cur.g, parent});
          parent = static_cast<int>(nodes.size()) - 1;
        }
        goal_node = parent;
        break;
      }
    }
    for (const Primitive& primitive : primitives_) {
      const Primitive p = OntoHeadingBins(cur.pose.yaw_rad(), primitive);
      const Pose2 next = Apply(cur.pose, p, 1.0);
      int nx, ny;
      if (!cell_of(next.x_m(), next.y_m(), &nx, &ny)) continue;
      // The length alone first: most successors are known no better without the clearance.
      const int direction = p.forward_m > 0.0 ? 1 : (p.forward_m < 0.0 ? -1 : cur.direction);
      const double cusp_m =
          cur.direction != 0 && direction != cur.direction ? params_.direction_switch_cost_m : 0.0;
      double g = cur.g + p.cost + cusp_m;
      const uint64_t state = state_of(nx, ny, bin_of(next.yaw_rad()));
      const auto known = best.find(state);
      if (known != best.end() && g >= known->second) continue;
      double escaped_m = -1.0;
      if (!SegmentFree(cur.pose, p)) {
        // Backing out: only while every step gains clearance, and not for long.
        const double travelled_m = cur.escaped_m + std::abs(p.forward_m) + std::abs(p.lateral_m);
        if (!escaping || travelled_m > params_.escape_m ||
            !(clearance_->At(next) > cur_clearance_m + 1e-3)) {
          continue;
        }
        escaped_m = travelled_m;
      }
      if (params_.clearance_weight > 0.0 || params_.coastal_weight > 0.0) {
        const double factor =
            (params_.clearance_weight > 0.0 ? ClearanceFactor(clearance_->At(next)) : 1.0) +
            CoastExtra(costmap_->DistanceToObstacle_m(nx, ny));
        g = cur.g + p.cost * factor + cusp_m;
        if (known != best.end() && g >= known->second) continue;
      }
      best[state] = static_cast<float>(g);
      nodes.push_back({next, g, id, escaped_m, direction});
      open.push(
          {g + params_.heuristic_weight * heuristic(next), static_cast<int>(nodes.size()) - 1});
    }
  }
  if (goal_node < 0) goal_node = loose_goal;
  int end = goal_node;
  if (end < 0) {
    if (!params_.allow_approximate) {
      return absl::NotFoundError(absl::StrCat("lattice: no path within ", request.time_limit_s,
                                              " s / ", params_.max_expansions, " expansions"));
    }
    result.exact = false;
    end = closest;
  }
  for (int id = end; id >= 0; id = nodes[id].parent) result.poses.push_back(nodes[id].pose);
  std::reverse(result.poses.begin(), result.poses.end());
  for (size_t i = 1; i < result.poses.size(); ++i) {
    result.length_m += (result.poses[i].translation() - result.poses[i - 1].translation()).norm();
  }
  return result;
}

absl::StatusOr<std::unique_ptr<SingleRobotPlanner>> MakeSingleRobotPlanner(
    Costmap* costmap, const RobotModel& model, const LatticeParams& params) {
  if (costmap == nullptr) return absl::InvalidArgumentError("costmap: null");
  if (absl::Status s = params.Validate(); !s.ok()) return s;
  if (absl::Status s = model.Validate(); !s.ok()) return s;
  if (model.kinematics == Kinematics::kAckermann &&
      !(model.limits.max_steering_rad > 0.0 && model.wheelbase_m > 0.0)) {
    return absl::InvalidArgumentError(
        "model: Ackermann needs wheelbase_m and max_steering_rad > 0");
  }
  return std::make_unique<LatticePlanner>(costmap, model, params);
}

}  // namespace fleetnav::planner
