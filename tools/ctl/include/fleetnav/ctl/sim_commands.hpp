#pragma once

#include <grpcpp/channel.h>

#include <memory>
#include <string>

#include "absl/status/status.h"
#include "fleetnav/ctl/commands.hpp"

namespace fleetnav::ctl {

/// Prints the simulator's ground truth: every robot's true pose and velocity, contacts and
/// minimum separation.
absl::Status PrintGroundTruth(const CommandContext& context,
                              std::shared_ptr<grpc::Channel> sim_channel);

/// Prints, for one robot, the pose fleetnavd holds beside the simulator's true pose and the
/// difference between them (metres, degrees).
absl::Status CompareWithTruth(const CommandContext& context,
                              std::shared_ptr<grpc::Channel> sim_channel,
                              const std::string& robot_id);

}  // namespace fleetnav::ctl
