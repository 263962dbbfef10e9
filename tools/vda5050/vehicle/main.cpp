// fleetnav-vda-vehicle: simulated VDA 5050 2.0 vehicles on an MQTT broker, for tests and
// benchmarks of fleetnav-vda5050 (docs/vda5050.md). Each vehicle has a broker connection of its
// own with its last will, publishes connection and factsheet (retained) and its state, takes
// orders and instant actions, and drives (SimulatedVehicle).
#include <pthread.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <memory>
#include <thread>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/synchronization/mutex.h"
#include "fleetnav/core/angles.hpp"
#include "fleetnav/core/clock.hpp"
#include "fleetnav/core/stop_signals.hpp"
#include "fleetnav/core/version.hpp"
#include "fleetnav/vda5050/mqtt_client.hpp"
#include "fleetnav/vda5050/simulated_vehicle.hpp"
#include "fleetnav/vda5050/vda_json.hpp"
#include "fleetnav/vda5050/vda_topics.hpp"

namespace {

namespace vda = fleetnav::vda5050;

/// One vehicle with its broker connection; the MQTT thread and the stepping thread share it.
struct Vehicle {
  absl::Mutex mutex;
  std::unique_ptr<vda::SimulatedVehicle> model ABSL_GUARDED_BY(mutex);
  std::unique_ptr<vda::MosquittoClient> mqtt ABSL_GUARDED_BY(mutex);
  std::string serial;
  std::string topic_prefix;  ///< INTERFACE/v2/MANUFACTURER/SERIAL/
  bool factsheet_asked ABSL_GUARDED_BY(mutex) = false;
};

/// The factsheet, then ONLINE, both retained (§6.15, §6.14): at the first connection and at
/// every reconnection, for a broker that restarted has lost them and a master control sends a
/// vehicle its running order again when it says ONLINE.
void Announce(Vehicle& vehicle, int64_t unix_ms) ABSL_EXCLUSIVE_LOCKS_REQUIRED(vehicle.mutex) {
  if (vehicle.mqtt == nullptr) return;
  (void)vehicle.mqtt->Publish(vehicle.topic_prefix + "factsheet",
                              vda::ToJson(vehicle.model->MakeFactsheet(unix_ms)), 1, true);
  (void)vehicle.mqtt->Publish(
      vehicle.topic_prefix + "connection",
      vda::ToJson(vehicle.model->MakeConnection(vda::ConnectionState::kOnline, unix_ms)), 1, true);
}

}  // namespace

int main(int argc, char** argv) {
  sigset_t stop_signals = fleetnav::BlockStopSignals();

  CLI::App app{"fleetnav-vda-vehicle: simulated VDA 5050 2.0 vehicles"};
  app.set_version_flag("--version", std::string(fleetnav::Version()));
  std::string broker_host = "127.0.0.1", interface_name = "uagv", truth_path;
  int broker_port = 1883, vehicles = 1, first_serial = 1;
  double state_hz = 2.0, step_hz = 50.0, spacing_m = 1.5;
  std::vector<double> start{0.0, 0.0, 0.0};
  vda::SimulatedVehicleParams params;
  params.factsheet.series_name = "fleetnav-sim";
  params.factsheet.agv_kinematic = "OMNI";
  params.factsheet.agv_class = "CARRIER";
  params.factsheet.max_load_mass_kg = 100.0;
  params.factsheet.width_m = 0.45;
  params.factsheet.length_m = 0.75;
  app.add_option("--broker-host", broker_host)->capture_default_str();
  app.add_option("--broker-port", broker_port)->capture_default_str();
  app.add_option("--interface", interface_name, "the topics' first level")->capture_default_str();
  app.add_option("--manufacturer", params.manufacturer)->capture_default_str();
  app.add_option("--vehicles", vehicles, "how many vehicles")
      ->check(CLI::Range(1, 10000))
      ->capture_default_str();
  app.add_option("--first-serial", first_serial, "serial numbers count from here (4 digits)")
      ->capture_default_str();
  app.add_option("--map", params.map_id, "the map id of positions")->required();
  app.add_option("--start", start, "the first vehicle's pose: x_m y_m yaw_deg")
      ->expected(3)
      ->capture_default_str();
  app.add_option("--spacing-m", spacing_m, "the others stand this far apart along +y")
      ->capture_default_str();
  app.add_option("--speed-mps", params.speed_mps)->capture_default_str();
  app.add_option("--kinematic", params.factsheet.agv_kinematic, "factsheet agvKinematic")
      ->check(CLI::IsMember({"DIFF", "OMNI", "THREEWHEEL"}))
      ->capture_default_str();
  app.add_option("--width-m", params.factsheet.width_m)->capture_default_str();
  app.add_option("--length-m", params.factsheet.length_m)->capture_default_str();
  app.add_option("--state-hz", state_hz, "state messages per vehicle per second")
      ->check(CLI::Range(0.1, 100.0))
      ->capture_default_str();
  app.add_option("--truth", truth_path,
                 "append each vehicle's true pose at 10 Hz: serial,x_m,y_m,yaw_rad,unix_ms");
  CLI11_PARSE(app, argc, argv);
  params.factsheet.speed_max_mps = params.speed_mps;

  fleetnav::SystemClock clock;
  std::vector<std::unique_ptr<Vehicle>> fleet;
  for (int i = 0; i < vehicles; ++i) {
    auto vehicle = std::make_unique<Vehicle>();
    vda::SimulatedVehicleParams own = params;
    own.serial_number = absl::StrFormat("%04d", first_serial + i);
    own.start = fleetnav::Pose2(start[0], start[1] + spacing_m * i, fleetnav::DegToRad(start[2]));
    vehicle->serial = own.serial_number;
    vehicle->topic_prefix =
        vda::TopicFor(interface_name, params.manufacturer, own.serial_number, "");
    {
      absl::MutexLock lock(&vehicle->mutex);
      vehicle->model = std::make_unique<vda::SimulatedVehicle>(own);
    }
    const std::string& prefix = vehicle->topic_prefix;
    vda::MqttOptions options;
    options.host = broker_host;
    options.port = broker_port;
    options.client_id = absl::StrCat("vda-vehicle-", params.manufacturer, "-", own.serial_number);
    {
      absl::MutexLock lock(&vehicle->mutex);
      options.will =
          vda::MqttOptions::Will{prefix + "connection",
                                 vda::ToJson(vehicle->model->MakeConnection(
                                     vda::ConnectionState::kConnectionBroken, clock.UnixMs())),
                                 1, true};
    }
    Vehicle* raw = vehicle.get();
    absl::StatusOr<std::unique_ptr<vda::MosquittoClient>> mqtt = vda::MosquittoClient::Connect(
        options,
        [raw](const std::string& at, const std::string& payload) {
          absl::MutexLock lock(&raw->mutex);
          if (at == raw->topic_prefix + "order") {
            raw->model->OnOrder(payload);
            const std::vector<vda::VehicleError>& errors = raw->model->errors();
            if (!errors.empty()) {
              std::fprintf(stderr, "fleetnav-vda-vehicle %s: order refused: %s: %s\n",
                           raw->serial.c_str(), errors.back().error_type.c_str(),
                           errors.back().description.c_str());
            }
          }
          if (at == raw->topic_prefix + "instantActions" && raw->model->OnInstantActions(payload)) {
            raw->factsheet_asked = true;
          }
        },
        [raw, &clock](bool /*reconnected*/) {
          absl::MutexLock lock(&raw->mutex);
          Announce(*raw, clock.UnixMs());  // not yet kept at the first connection: see below
        },
        10.0);
    if (!mqtt.ok()) {
      std::fprintf(stderr, "fleetnav-vda-vehicle: %s\n",
                   std::string(mqtt.status().message()).c_str());
      return 1;
    }
    (void)(*mqtt)->Subscribe(prefix + "order", 1);
    (void)(*mqtt)->Subscribe(prefix + "instantActions", 1);
    {
      absl::MutexLock lock(&vehicle->mutex);
      vehicle->mqtt = *std::move(mqtt);
      Announce(*vehicle, clock.UnixMs());
    }
    fleet.push_back(std::move(vehicle));
  }
  std::fprintf(stderr, "fleetnav-vda-vehicle: %d vehicles of %s online on %s:%d\n", vehicles,
               params.manufacturer.c_str(), broker_host.c_str(), broker_port);

  std::ofstream truth;
  if (!truth_path.empty()) truth.open(truth_path, std::ios::app);
  const auto step_period = std::chrono::duration<double>(1.0 / step_hz);
  const int steps_per_state = std::max(1, static_cast<int>(step_hz / state_hz));
  const int steps_per_truth = std::max(1, static_cast<int>(step_hz / 10.0));
  auto next = std::chrono::steady_clock::now();
  timespec no_wait{};
  for (int64_t tick = 0;; ++tick) {
    if (sigtimedwait(&stop_signals, nullptr, &no_wait) > 0) break;
    const int64_t now_ms = clock.UnixMs();
    for (size_t i = 0; i < fleet.size(); ++i) {
      Vehicle& vehicle = *fleet[i];
      absl::MutexLock lock(&vehicle.mutex);
      const vda::VehicleStepEvents events = vehicle.model->Step(1.0 / step_hz, now_ms);
      if (events.first_motion) {
        std::printf(
            "{\"event\":\"first_motion\",\"serial\":\"%s\",\"order_id\":\"%s\",\"unix_ms\":%lld}\n",
            vehicle.serial.c_str(), events.moving_order_id.c_str(), static_cast<long long>(now_ms));
        std::fflush(stdout);
      }
      // Staggered over the vehicles, and at once on an event (§6.10).
      if (events.changed || (tick + static_cast<int64_t>(i)) % steps_per_state == 0) {
        (void)vehicle.mqtt->Publish(vehicle.topic_prefix + "state",
                                    vda::ToJson(vehicle.model->MakeState(now_ms)), 0, false);
      }
      if (vehicle.factsheet_asked) {
        vehicle.factsheet_asked = false;
        (void)vehicle.mqtt->Publish(vehicle.topic_prefix + "factsheet",
                                    vda::ToJson(vehicle.model->MakeFactsheet(now_ms)), 1, true);
      }
      if (truth.is_open() && tick % steps_per_truth == 0) {
        const fleetnav::Pose2& pose = vehicle.model->pose();
        truth << vehicle.serial << ',' << pose.x_m() << ',' << pose.y_m() << ',' << pose.yaw_rad()
              << ',' << now_ms << '\n';
      }
    }
    if (truth.is_open()) truth.flush();
    next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(step_period);
    std::this_thread::sleep_until(next);
  }
  // A planned disconnect: OFFLINE, then a clean disconnect (no last will, §6.14).
  for (std::unique_ptr<Vehicle>& vehicle : fleet) {
    absl::MutexLock lock(&vehicle->mutex);
    (void)vehicle->mqtt->Publish(
        vehicle->topic_prefix + "connection",
        vda::ToJson(vehicle->model->MakeConnection(vda::ConnectionState::kOffline, clock.UnixMs())),
        1, true);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  for (std::unique_ptr<Vehicle>& vehicle : fleet) {
    absl::MutexLock lock(&vehicle->mutex);
    vehicle->mqtt->Disconnect();
  }
  return 0;
}
