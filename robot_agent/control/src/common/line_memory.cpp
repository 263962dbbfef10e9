#include "fleetnav/robot_agent/control/common/line_memory.hpp"

#include <Eigen/Eigenvalues>

namespace fleetnav::agent {
namespace {

constexpr size_t kMinPoints = 10;
constexpr double kMinSpanM = 0.5;

}  // namespace

void LineMemory::Assume(const Eigen::Vector2d& point, const Eigen::Vector2d& direction) {
  point_ = point;
  direction_ = direction.normalized();
}

void LineMemory::Add(const Eigen::Vector2d& point_in_map, double travelled_m,
                     const Eigen::Vector2d& heading) {
  samples_.push_back({point_in_map, travelled_m});
  while (!samples_.empty() && samples_.front().travelled_m < travelled_m - memory_m_) {
    samples_.pop_front();
  }
  Fit(heading);
}

double LineMemory::SignedDistance(const Eigen::Vector2d& p) const {
  const Eigen::Vector2d normal(-direction_.y(), direction_.x());
  return (p - point_).dot(normal);
}

void LineMemory::Fit(const Eigen::Vector2d& heading) {
  if (samples_.size() < kMinPoints ||
      samples_.back().travelled_m - samples_.front().travelled_m < kMinSpanM) {
    return;
  }
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const Sample& s : samples_) mean += s.point;
  mean /= static_cast<double>(samples_.size());
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (const Sample& s : samples_) {
    const Eigen::Vector2d d = s.point - mean;
    scatter += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(scatter);
  Eigen::Vector2d direction = solver.eigenvectors().col(1);  // the largest eigenvalue's
  if (direction.dot(heading) < 0.0) direction = -direction;
  point_ = mean;
  direction_ = direction.normalized();
}

}  // namespace fleetnav::agent
