#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace fleetnav::server {

/// Latency figures of one kind of computation (a dispatcher pass, a traffic search): how many
/// there were, and percentiles over the latest ones (milliseconds of computing time).
struct PassFigures {
  int64_t count = 0;
  double p50_ms = 0.0;
  double p99_ms = 0.0;
  double max_ms = 0.0;
};

/// The latest `capacity` durations of one kind of computation and how many there were in all: a
/// server runs for months, so older samples are overwritten. Not thread-safe.
class PassTimings {
 public:
  explicit PassTimings(size_t capacity = 100'000) : capacity_(capacity) {}
  void Add(double ms);
  PassFigures Figures() const;

 private:
  size_t capacity_;
  std::vector<double> ms_;
  int64_t count_ = 0;
};

/// CPU time the calling thread has used, in milliseconds (a computing-time measure, not a clock
/// of the logic).
double ThreadCpuMs();

}  // namespace fleetnav::server
