#pragma once

#include <grpcpp/channel.h>

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include "absl/status/statusor.h"
#include "absl/synchronization/mutex.h"
#include "absl/synchronization/notification.h"
#include "fleetnav/core/clock.hpp"
#include "fleetnav/core/robot_model.hpp"
#include "fleetnav/robot_agent/server_link.hpp"
#include "fleetnav/v1/fleet_service.grpc.pb.h"
#include "fleetnav/vda5050/mqtt_client.hpp"
#include "fleetnav/vda5050/vda_messages.hpp"
#include "fleetnav/vda5050/vehicle_session.hpp"

namespace fleetnav::vda5050 {

struct BridgeParams {
  std::string interface_name = "uagv";  ///< the first topic level (§6.3)
  /// The fleetnav robot kind that stands for the vehicles (traffic footprint, planning): a
  /// vehicle whose factsheet names other kinematics, or a larger size, is not registered.
  std::string kind = "mecanum-platform";
  /// Nodes of a planned path at most this far apart (more where it turns).
  double node_spacing_m = 2.0;
  JobOrderParams order;
  double pump_period_s = 0.02;  ///< how often assignments and commands are turned into messages
};

/// Counts of what the bridge took and left, for its log and figures.
struct BridgeCounters {
  uint64_t states = 0;             ///< state messages turned into telemetry
  uint64_t refused_malformed = 0;  ///< failed the JSON checks (logged)
  uint64_t refused_stale = 0;      ///< header id did not grow (logged)
  uint64_t refused_unknown = 0;    ///< from a vehicle not registered (logged)
  uint64_t orders = 0;             ///< order messages published (updates included)
  uint64_t instant_actions = 0;
  int vehicles = 0;  ///< registered now
};

/// fleetnav-vda5050: third-party vehicles that speak VDA 5050 2.0 over MQTT as fleetnav robots.
/// A vehicle that says `connection` ONLINE and has published its `factsheet` is registered
/// with fleetnavd as robot vda-<manufacturer>-<serial> (an AgentService stream of its own, as a
/// fleetnav agent has), of BridgeParams::kind, able to run free-navigation actions. A job
/// fleetnavd assigns to it is planned with FleetService.PlanPaths from the vehicle's position
/// through each action's waypoints to its goal, and sent as an `order` whose base grows with
/// the traffic clearances (JobOrder); cancel and pause go as `instantActions`. The vehicle's
/// `state` becomes the robot's telemetry and job events (VehicleSession); `visualization`
/// updates the pose between states. Malformed messages (JSON checks citing the specification),
/// stale header ids and unknown vehicles are logged and left out, never fatal. Orders go with
/// QoS 1 (kept by the MQTT client while the broker is away), and a vehicle that comes back
/// ONLINE is sent its running order again (one that kept it ignores the copy, §6.6.4.3), so none
/// is lost. Thread-safe.
class VdaBridge {
 public:
  VdaBridge(BridgeParams params, std::shared_ptr<grpc::Channel> fleetnavd, const Clock* clock,
            std::function<void(const std::string&)> log);
  ~VdaBridge();
  VdaBridge(const VdaBridge&) = delete;
  VdaBridge& operator=(const VdaBridge&) = delete;

  /// Subscribes to the vehicles' topics on `mqtt` and starts the pump thread.
  absl::Status Start(MqttClient* mqtt);
  void Stop();
  /// Every MQTT message (the client's thread).
  void OnMessage(const std::string& topic, const std::string& payload);
  BridgeCounters counters() const;

 private:
  struct Vehicle {
    std::string manufacturer;
    std::string serial;
    std::optional<Factsheet> factsheet;
    bool online = false;
    bool refused = false;  ///< its factsheet does not fit --kind (logged once)
    VehicleSession session;
    std::unique_ptr<agent::ServerLink> link;
    uint32_t order_header_id = 0;  ///< headerIds count per topic (§6.4)
    uint32_t instant_header_id = 0;
    int next_action_id = 0;
    std::map<std::string, int> clearances;  ///< latest per job, until it starts
  };
  Vehicle& VehicleFor(const std::string& manufacturer, const std::string& serial)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  /// Registers the vehicle with fleetnavd when it is online with a factsheet that fits.
  void MaybeRegister(Vehicle& vehicle) ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  void Publish(Vehicle& vehicle, const std::string& topic, const std::string& payload)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  /// The bridge's header for `vehicle` with the next id of the topic `counter` counts (§6.4).
  Header NextHeader(const Vehicle& vehicle, uint32_t* counter) const;
  void PublishOrder(Vehicle& vehicle, Order order) ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  void PublishInstant(Vehicle& vehicle, Action action) ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  void PumpOnce();
  /// The waypoints of `assignment` from `start`, planned on fleetnavd's map.
  absl::StatusOr<std::vector<OrderWaypoint>> PlanWaypoints(const JobAssignment& assignment,
                                                           const Pose2& start,
                                                           const std::string& robot_id);
  void Log(const std::string& line) const {
    if (log_) log_(line);
  }

  const BridgeParams params_;
  std::shared_ptr<grpc::Channel> channel_;
  std::unique_ptr<v1::FleetService::Stub> fleet_;
  const Clock* clock_;
  std::function<void(const std::string&)> log_;
  RobotModel model_;
  MqttClient* mqtt_ = nullptr;
  mutable absl::Mutex mutex_;
  std::map<std::string, std::unique_ptr<Vehicle>> vehicles_ ABSL_GUARDED_BY(mutex_);
  BridgeCounters counters_ ABSL_GUARDED_BY(mutex_);
  absl::Notification stop_;
  std::thread pump_;
};

}  // namespace fleetnav::vda5050
