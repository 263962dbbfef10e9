#include <ompl/base/PlannerTerminationCondition.h>
#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/ScopedState.h>
#include <ompl/base/spaces/ReedsSheppStateSpace.h>
#include <ompl/geometric/PathSimplifier.h>

#include <algorithm>
#include <cmath>
#include <exception>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/angles.hpp"
#include "ompl_common_internal.hpp"

namespace fleetnav::planner {

absl::Status OmplPlannerParams::Validate() const {
  if (seed == 0) return absl::InvalidArgumentError("seed: must be > 0");
  if (!(range >= 0.0) || !std::isfinite(range)) {
    return absl::InvalidArgumentError("range: must be finite and >= 0");
  }
  if (!(motion_check_resolution_cells > 0.0 && motion_check_resolution_cells <= 1.0)) {
    return absl::InvalidArgumentError("motion_check_resolution_cells: must be in (0, 1]");
  }
  return absl::OkStatus();
}

namespace internal {

namespace ob = ompl::base;
namespace og = ompl::geometric;

using Se2State = ob::SE2StateSpace::StateType;

void SetPose(const Pose2& pose, ob::State* state) {
  Se2State* s = state->as<Se2State>();
  s->setXY(pose.x_m(), pose.y_m());
  // OMPL's SO(2) bounds are [-pi, pi); poses keep yaws in (-pi, pi].
  double yaw = std::remainder(pose.yaw_rad(), 2.0 * kPi);
  if (yaw >= kPi) yaw -= 2.0 * kPi;
  s->setYaw(yaw);
}

Pose2 GetPose(const ob::State* state) {
  const Se2State* s = state->as<Se2State>();
  return Pose2(s->getX(), s->getY(), s->getYaw());
}

SeededSe2Sampler::SeededSe2Sampler(const ob::StateSpace* space, uint32_t seed)
    : ob::StateSampler(space) {
  rng_.setLocalSeed(seed);
}

void SeededSe2Sampler::Clamp(Se2State* s) const {
  const ob::RealVectorBounds& b = space_->as<ob::SE2StateSpace>()->getBounds();
  s->setXY(std::clamp(s->getX(), b.low[0], b.high[0]), std::clamp(s->getY(), b.low[1], b.high[1]));
  s->setYaw(std::remainder(s->getYaw(), 2.0 * kPi));
}

void SeededSe2Sampler::sampleUniform(ob::State* state) {
  const ob::RealVectorBounds& b = space_->as<ob::SE2StateSpace>()->getBounds();
  Se2State* s = state->as<Se2State>();
  s->setXY(rng_.uniformReal(b.low[0], b.high[0]), rng_.uniformReal(b.low[1], b.high[1]));
  s->setYaw(rng_.uniformReal(-kPi, kPi));
}

void SeededSe2Sampler::sampleUniformNear(ob::State* state, const ob::State* near, double distance) {
  const Se2State* n = near->as<Se2State>();
  Se2State* s = state->as<Se2State>();
  s->setXY(rng_.uniformReal(n->getX() - distance, n->getX() + distance),
           rng_.uniformReal(n->getY() - distance, n->getY() + distance));
  s->setYaw(n->getYaw() + rng_.uniformReal(-distance, distance));
  Clamp(s);
}

void SeededSe2Sampler::sampleGaussian(ob::State* state, const ob::State* mean, double std_dev) {
  const Se2State* m = mean->as<Se2State>();
  Se2State* s = state->as<Se2State>();
  s->setXY(rng_.gaussian(m->getX(), std_dev), rng_.gaussian(m->getY(), std_dev));
  s->setYaw(rng_.gaussian(m->getYaw(), std_dev));
  Clamp(s);
}

bool FootprintValidityChecker::isValid(const ob::State* state) const {
  const Se2State* s = state->as<Se2State>();
  return costmap_->PoseFree(s->getX(), s->getY(), s->getYaw());
}

FootprintMotionValidator::FootprintMotionValidator(ob::SpaceInformation* si, double step_m,
                                                   double corner_radius_m, double turning_radius_m)
    : ob::MotionValidator(si),
      step_m_(step_m),
      corner_radius_m_(corner_radius_m),
      turning_radius_m_(turning_radius_m) {}

int FootprintMotionValidator::FirstInvalid(const ob::State* s1, const ob::State* s2, int* steps,
                                           ob::State* scratch) const {
  const ob::StateSpace* space = si_->getStateSpace().get();
  if (turning_radius_m_ > 0.0) {
    const auto* rs = space->as<ob::ReedsSheppStateSpace>();
    ob::ReedsSheppStateSpace::ReedsSheppPath path = rs->reedsShepp(s1, s2);
    const double length_m = turning_radius_m_ * path.length();
    const double sweep_m = length_m * (1.0 + corner_radius_m_ / turning_radius_m_);
    *steps = std::max(1, static_cast<int>(std::ceil(sweep_m / step_m_)));
    bool first_time = false;
    for (int k = 1; k <= *steps; ++k) {
      if (k == *steps) {
        if (!si_->isValid(s2)) return k;
        continue;
      }
      rs->interpolate(s1, s2, static_cast<double>(k) / *steps, first_time, path, scratch);
      if (!si_->isValid(scratch)) return k;
    }
    return 0;
  }
  const Pose2 a = GetPose(s1), b = GetPose(s2);
  const double sweep_m =
      (b.translation() - a.translation()).norm() +
      corner_radius_m_ * std::abs(std::remainder(b.yaw_rad() - a.yaw_rad(), 2.0 * kPi));
  *steps = std::max(1, static_cast<int>(std::ceil(sweep_m / step_m_)));
  for (int k = 1; k <= *steps; ++k) {
    if (k == *steps) {
      if (!si_->isValid(s2)) return k;
      continue;
    }
    space->interpolate(s1, s2, static_cast<double>(k) / *steps, scratch);
    if (!si_->isValid(scratch)) return k;
  }
  return 0;
}

bool FootprintMotionValidator::checkMotion(const ob::State* s1, const ob::State* s2) const {
  ob::State* scratch = si_->allocState();
  int steps = 0;
  const bool ok = FirstInvalid(s1, s2, &steps, scratch) == 0;
  si_->freeState(scratch);
  (ok ? valid_ : invalid_)++;
  return ok;
}

bool FootprintMotionValidator::checkMotion(const ob::State* s1, const ob::State* s2,
                                           std::pair<ob::State*, double>& last_valid) const {
  ob::State* scratch = si_->allocState();
  int steps = 0;
  const int bad = FirstInvalid(s1, s2, &steps, scratch);
  if (bad == 0) {
    si_->freeState(scratch);
    ++valid_;
    return true;
  }
  last_valid.second = static_cast<double>(bad - 1) / steps;
  if (last_valid.first != nullptr) {
    si_->getStateSpace()->interpolate(s1, s2, last_valid.second, last_valid.first);
  }
  si_->freeState(scratch);
  ++invalid_;
  return false;
}

SeededRrtConnect::SeededRrtConnect(const ob::SpaceInformationPtr& si, uint32_t seed)
    : og::RRTConnect(si) {
  rng_.setLocalSeed(seed);
}

std::vector<const ob::State*> SeededRrtConnect::ClosestStartTreePath(const ob::State* goal) const {
  std::vector<const ob::State*> out;
  if (!tStart_ || tStart_->size() == 0) return out;
  std::vector<Motion*> motions;
  tStart_->list(motions);
  const Motion* best = nullptr;
  double best_d = 0.0;
  for (const Motion* m : motions) {
    const double d = si_->distance(m->state, goal);
    if (best == nullptr || d < best_d) {
      best = m;
      best_d = d;
    }
  }
  for (const Motion* m = best; m != nullptr; m = m->parent) out.push_back(m->state);
  std::reverse(out.begin(), out.end());
  return out;
}

int64_t SeededRrtConnect::TreeSize() const {
  return static_cast<int64_t>((tStart_ ? tStart_->size() : 0) + (tGoal_ ? tGoal_->size() : 0));
}

namespace {

// Spacing (in the space's distance, about metres) of the states tried as shortcut ends.
constexpr double kShortcutSpacing = 1.0;

// From each kept vertex, jump to the farthest later vertex reachable by one valid motion.
void GreedyShortcut(const ob::SpaceInformationPtr& si, og::PathGeometric& path,
                    const std::stop_token& stop) {
  std::vector<ob::State*>& states = path.getStates();
  const size_t n = states.size();
  if (n < 3) return;
  std::vector<bool> keep(n, false);
  keep[0] = true;
  size_t i = 0;
  while (i + 1 < n) {
    size_t j = n - 1;
    while (j > i + 1 && (stop.stop_requested() || !si->checkMotion(states[i], states[j]))) --j;
    keep[j] = true;
    i = j;
  }
  std::vector<ob::State*> kept;
  for (size_t k = 0; k < n; ++k) {
    if (keep[k]) {
      kept.push_back(states[k]);
    } else {
      si->freeState(states[k]);
    }
  }
  states = std::move(kept);
}

}  // namespace

absl::StatusOr<PathResult> PlanWithOmpl(const OmplProblem& problem, Costmap* costmap,
                                        const OmplPlannerParams& params, const PathRequest& request,
                                        std::stop_token stop) {
  if (absl::Status s = params.Validate(); !s.ok()) return s;
  if (absl::Status s = request.Validate(); !s.ok()) return s;
  const double res = costmap->resolution_m();
  const double width_m = costmap->width() * res, height_m = costmap->height() * res;
  auto inside = [&](const Pose2& p) {
    return p.x_m() >= 0.0 && p.y_m() >= 0.0 && p.x_m() < width_m && p.y_m() < height_m;
  };
  if (!inside(request.start) ||
      !costmap->PoseFree(request.start.x_m(), request.start.y_m(), request.start.yaw_rad())) {
    return absl::InvalidArgumentError("start: outside the map or in collision");
  }
  if (!inside(request.goal)) return absl::InvalidArgumentError("goal: outside the map");
  if (!costmap->PoseFree(request.goal.x_m(), request.goal.y_m(), request.goal.yaw_rad())) {
    return absl::InvalidArgumentError("goal: in collision");
  }
  try {
    ob::RealVectorBounds bounds(2);
    bounds.setLow(0, 0.0);
    bounds.setHigh(0, width_m);
    bounds.setLow(1, 0.0);
    bounds.setHigh(1, height_m);
    problem.space->setBounds(bounds);
    auto next_seed = std::make_shared<uint32_t>(params.seed);
    problem.space->setStateSamplerAllocator([next_seed](const ob::StateSpace* space) {
      return std::make_shared<SeededSe2Sampler>(space, (*next_seed)++);
    });
    auto si = std::make_shared<ob::SpaceInformation>(problem.space);
    si->setStateValidityChecker(std::make_shared<FootprintValidityChecker>(si.get(), costmap));
    si->setMotionValidator(std::make_shared<FootprintMotionValidator>(
        si.get(), params.motion_check_resolution_cells * res, costmap->circumscribed_radius_m(),
        problem.turning_radius_m));
    si->setup();

    ob::ScopedState<> start(problem.space), goal(problem.space);
    SetPose(request.start, start.get());
    SetPose(request.goal, goal.get());
    auto pdef = std::make_shared<ob::ProblemDefinition>(si);
    pdef->setStartAndGoalStates(start, goal,
                                std::min(request.goal_tolerance_m, request.goal_tolerance_rad));
    auto planner = std::make_shared<SeededRrtConnect>(si, params.seed);
    if (params.range > 0.0) planner->setRange(params.range);
    planner->setProblemDefinition(pdef);
    planner->setup();
    const ob::PlannerTerminationCondition ptc = ob::plannerOrTerminationCondition(
        ob::timedPlannerTerminationCondition(request.time_limit_s),
        ob::PlannerTerminationCondition([&stop] { return stop.stop_requested(); }));
    const ob::PlannerStatus status = planner->solve(ptc);
    if (stop.stop_requested()) return absl::CancelledError(absl::StrCat(problem.name, ": stopped"));

    PathResult result;
    result.expanded = planner->TreeSize();
    og::PathGeometric path(si);
    if (status == ob::PlannerStatus::EXACT_SOLUTION) {
      path = *pdef->getSolutionPath()->as<og::PathGeometric>();
    } else if (status == ob::PlannerStatus::APPROXIMATE_SOLUTION ||
               status == ob::PlannerStatus::TIMEOUT) {
      // RRTConnect's own approximate path may bridge the two trees; the start-tree branch
      // closest to the goal is made of valid motions only.
      if (!params.allow_approximate) {
        return absl::NotFoundError(
            absl::StrCat(problem.name, ": no path within ", request.time_limit_s, " s"));
      }
      for (const ob::State* s : planner->ClosestStartTreePath(goal.get())) path.append(s);
      result.exact = false;
    } else if (status == ob::PlannerStatus::INVALID_START) {
      return absl::InvalidArgumentError(absl::StrCat("start: ", status.asString()));
    } else if (status == ob::PlannerStatus::INVALID_GOAL) {
      return absl::InvalidArgumentError(absl::StrCat("goal: ", status.asString()));
    } else {
      return absl::InternalError(absl::StrCat(problem.name, ": ", status.asString()));
    }
    if (path.getStateCount() == 0) path.append(start.get());
    if (params.simplify && path.getStateCount() > 2) {
      og::PathSimplifier simplifier(si);
      simplifier.collapseCloseVertices(path);
      // Shortcuts may start and end between RRTConnect's far-apart vertices: subdivide first
      // (about every metre), then jump greedily; twice, so the second pass cuts the corners
      // the first one left at its new vertices.
      for (int pass = 0; pass < 2; ++pass) {
        path.interpolate(static_cast<unsigned>(std::ceil(path.length() / kShortcutSpacing)) + 1);
        GreedyShortcut(si, path, stop);
      }
    }
    result.poses = problem.to_poses(path);
    for (size_t i = 1; i < result.poses.size(); ++i) {
      result.length_m += (result.poses[i].translation() - result.poses[i - 1].translation()).norm();
    }
    return result;
  } catch (const std::exception& e) {
    return absl::InternalError(absl::StrCat(problem.name, ": OMPL threw: ", e.what()));
  }
}

}  // namespace internal
}  // namespace fleetnav::planner
