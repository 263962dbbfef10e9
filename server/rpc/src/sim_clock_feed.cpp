#include "fleetnav/server/rpc/sim_clock_feed.hpp"

#include <grpcpp/grpcpp.h>

#include <chrono>

#include "absl/strings/str_cat.h"

namespace fleetnav::server {

SimClockFeed::SimClockFeed(const std::string& sim_address, ManualClock* clock, double poll_period_s)
    : address_(sim_address),
      clock_(clock),
      poll_period_s_(poll_period_s),
      stub_(v1::SimService::NewStub(
          grpc::CreateChannel(sim_address, grpc::InsecureChannelCredentials()))) {}

SimClockFeed::~SimClockFeed() { Stop(); }

bool SimClockFeed::ReadOnce(double deadline_s) {
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() +
                       std::chrono::milliseconds(static_cast<int64_t>(deadline_s * 1000)));
  v1::GroundTruth truth;
  if (!stub_->GetGroundTruth(&context, v1::GetGroundTruthRequest{}, &truth).ok()) return false;
  // The simulation's calendar, once: every start of fleetnavd (and every replica) stamps its
  // records alike, so a job's end reads as the same sim time whichever server recorded it.
  if (!calendar_set_ && truth.start_unix_ms() > 0) {
    clock_->SetUnixMsAtZero(truth.start_unix_ms());
    calendar_set_ = true;
  }
  clock_->SetNs(truth.sim_time_ns());
  return true;
}

absl::Status SimClockFeed::Start(double timeout_s) {
  const auto give_up = std::chrono::steady_clock::now() +
                       std::chrono::milliseconds(static_cast<int64_t>(timeout_s * 1000));
  while (!ReadOnce(1.0)) {
    if (std::chrono::steady_clock::now() >= give_up) {
      return absl::UnavailableError(absl::StrCat("--clock sim: the simulator at ", address_,
                                                 " did not answer GetGroundTruth within ",
                                                 timeout_s, " s"));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  thread_ = std::thread([this] {
    const auto period = std::chrono::microseconds(static_cast<int64_t>(poll_period_s_ * 1e6));
    while (!stopping_.load()) {
      (void)ReadOnce(1.0);  // a simulator that went away leaves the time where it was
      std::this_thread::sleep_for(period);
    }
  });
  return absl::OkStatus();
}

void SimClockFeed::Stop() {
  stopping_.store(true);
  if (thread_.joinable()) thread_.join();
}

}  // namespace fleetnav::server
