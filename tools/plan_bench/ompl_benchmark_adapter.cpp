#include "ompl_benchmark_adapter.hpp"

#include <ompl/base/ScopedState.h>
#include <ompl/base/goals/GoalState.h>
#include <ompl/base/spaces/SE2StateSpace.h>
#include <ompl/geometric/PathGeometric.h>

#include <chrono>
#include <cmath>
#include <stop_token>
#include <thread>

#include "fleetnav/core/angles.hpp"

namespace fleetnav::planner {

namespace ob = ompl::base;

namespace {

Pose2 GetPose(const ob::State* state) {
  const auto* se2 = state->as<ob::SE2StateSpace::StateType>();
  return Pose2(se2->getX(), se2->getY(), se2->getYaw());
}

void SetPose(const Pose2& pose, ob::State* state) {
  auto* se2 = state->as<ob::SE2StateSpace::StateType>();
  se2->setXY(pose.x_m(), pose.y_m());
  // OMPL's SO(2) bounds are [-pi, pi).
  const double yaw = std::remainder(pose.yaw_rad(), 2.0 * kPi);
  se2->setYaw(yaw >= kPi ? yaw - 2.0 * kPi : yaw);
}

}  // namespace

SingleRobotPlannerAdapter::SingleRobotPlannerAdapter(const ob::SpaceInformationPtr& si,
                                                     const std::string& name, Factory make,
                                                     const PathRequest& request)
    : ob::Planner(si, name), make_(std::move(make)), request_(request) {
  specs_.approximateSolutions = true;
  specs_.recognizedGoal = ob::GOAL_STATE;
}

ob::PlannerStatus SingleRobotPlannerAdapter::solve(const ob::PlannerTerminationCondition& ptc) {
  checkValidity();
  const ob::State* start = pis_.nextStart();
  const auto* goal = pdef_->getGoal() ? pdef_->getGoal()->as<ob::GoalState>() : nullptr;
  if (start == nullptr) return ob::PlannerStatus::INVALID_START;
  if (goal == nullptr || goal->getState() == nullptr) return ob::PlannerStatus::INVALID_GOAL;
  PathRequest request = request_;
  request.start = GetPose(start);
  request.goal = GetPose(goal->getState());

  absl::StatusOr<std::unique_ptr<SingleRobotPlanner>> planner = make_(run_++);
  if (!planner.ok()) {
    last_ = planner.status();
    return ob::PlannerStatus::ABORT;
  }
  std::stop_source stop;
  {
    // OMPL's termination condition is polled here and turned into a stop request.
    std::jthread watcher([&](std::stop_token done) {
      while (!done.stop_requested()) {
        if (ptc()) {
          stop.request_stop();
          return;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
    });
    last_ = (*planner)->Plan(request, stop.get_token());
  }
  if (!last_.ok()) {
    switch (last_.status().code()) {
      case absl::StatusCode::kInvalidArgument:
        return last_.status().message().rfind("goal", 0) == 0 ? ob::PlannerStatus::INVALID_GOAL
                                                              : ob::PlannerStatus::INVALID_START;
      case absl::StatusCode::kCancelled:
      case absl::StatusCode::kDeadlineExceeded:
      case absl::StatusCode::kNotFound:
        return ob::PlannerStatus::TIMEOUT;
      default:
        return ob::PlannerStatus::CRASH;
    }
  }
  auto path = std::make_shared<ompl::geometric::PathGeometric>(si_);
  ob::State* state = si_->allocState();
  for (const Pose2& pose : last_->poses) {
    SetPose(pose, state);
    path->append(state);
  }
  si_->freeState(state);
  const bool approximate = !last_->exact;
  const double difference =
      approximate && !last_->poses.empty()
          ? (last_->poses.back().translation() - request.goal.translation()).norm()
          : 0.0;
  pdef_->addSolutionPath(path, approximate, difference, getName());
  return {true, approximate};
}

}  // namespace fleetnav::planner
