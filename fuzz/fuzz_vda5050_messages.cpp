// Fuzz target: the VDA 5050 messages a broker delivers to the bridge (state, visualization,
// connection, factsheet) and to a vehicle (order, instant actions). The first byte picks the
// message, the rest is its JSON. Whatever parses is also fed to what consumes it: a state to a
// vehicle session running a job, an order and instant actions to the simulated vehicle. No input
// may crash or hang them.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fleetnav/vda5050/job_order.hpp"
#include "fleetnav/vda5050/simulated_vehicle.hpp"
#include "fleetnav/vda5050/vda_json.hpp"
#include "fleetnav/vda5050/vehicle_session.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  namespace vda = fleetnav::vda5050;
  const std::string json(reinterpret_cast<const char*>(data + 1), size - 1);
  switch (data[0] % 6) {
    case 0: {
      absl::StatusOr<vda::State> state = vda::ParseState(json);
      if (!state.ok()) break;
      vda::VehicleSession session("vda-fuzz-0001");
      absl::StatusOr<vda::JobOrder> order = vda::JobOrder::Create(
          "job-1-5", "m",
          {{0, 0, std::nullopt, 0, false}, {1, 0, 0.0, 0, true}, {2, 2, 1.0, 1, true}});
      (void)session.Start("job-1", *std::move(order));
      (void)session.Clear("job-1", 1);
      (void)session.OnState(*state, 0);
      break;
    }
    case 1:
      (void)vda::ParseVisualization(json);
      break;
    case 2:
      (void)vda::ParseConnection(json);
      break;
    case 3:
      (void)vda::ParseFactsheet(json);
      break;
    case 4:
    case 5: {
      vda::SimulatedVehicleParams params;
      params.map_id = "m";
      vda::SimulatedVehicle vehicle(params);
      if (data[0] % 6 == 4) {
        vehicle.OnOrder(json);
      } else {
        vehicle.OnInstantActions(json);
      }
      for (int i = 0; i < 20; ++i) vehicle.Step(0.05, 0);
      (void)vda::ToJson(vehicle.MakeState(0));
      break;
    }
  }
  return 0;
}
