#include "its-station/station/station_config.hpp"

#include "common/map/scenario_map.hpp"

namespace tb::its::station {

StationConfig make_station_config(std::uint32_t station_id, const scenario::Scenario* scenario,
                                  const scenario::Vehicle* vehicle, const StationOverrides& o) {
  StationConfig c;
  c.station_id = station_id;

  facilities::CaConfig& ca = c.ca;
  ca.station_id = station_id;
  ca.station_type = static_cast<messages::StationType>(
      o.station_type >= 0 ? o.station_type : (vehicle ? vehicle->station_type : 5));
  if (scenario)
    ca.policy = scenario->cam;
  if (vehicle) {
    ca.vehicle_length_m = vehicle->model.length_m;
    ca.vehicle_width_m = vehicle->model.width_m;
    // The scenario's role is the CDD VehicleRole, value for value.
    ca.vehicle_role = static_cast<messages::VehicleRole>(vehicle->role);
    if (vehicle->dangerous_goods)
      ca.dangerous_goods = static_cast<messages::DangerousGoodsBasic>(*vehicle->dangerous_goods);
  }
  // A pooled station traces what it sends, not every CAM it hears: 300 in range would write
  // 300 × 800 reception records a second (issue 33, docs/tracing.md).
  ca.trace_receptions =
      vehicle == nullptr || vehicle->station_kind != scenario::StationKind::kPooled;
  if (o.cam_policy == "fixed") {
    ca.policy.kind = scenario::CamPolicy::Kind::kFixed;
  } else if (o.cam_policy == "etsi") {
    ca.policy.kind = scenario::CamPolicy::Kind::kEtsi;
  }
  if (o.cam_period_ms > 0.0)
    ca.policy.period_ms = o.cam_period_ms;

  // Everything above the receiver works with the vehicle's orientation and the CAM reference
  // point (front centre), not the antenna's course and position (reference_position.hpp).
  if (vehicle) {
    c.antenna.vehicle_length_m = vehicle->model.length_m;
    c.antenna.antenna_forward_m = vehicle->model.antenna.forward_m;
    c.antenna.antenna_left_m = vehicle->model.antenna.left_m;
  }

  c.keep_alive_forwarding = !o.no_keep_alive_forwarding;
  c.denm_repetition_interval = std::chrono::duration_cast<clock::Duration>(
      std::chrono::duration<double, std::milli>(o.denm_repetition_ms));
  c.denm_repetition_duration = std::chrono::duration_cast<clock::Duration>(
      std::chrono::duration<double>(o.denm_repetition_duration_s));

  c.lcrw = !o.no_lcrw && (vehicle == nullptr || vehicle->station_lcrw);
  // A road-side unit (StationType 15) sends MAPEM/SPATEM; the vehicle's application is not its.
  c.signals = !o.no_signals && (vehicle == nullptr || vehicle->station_signals) &&
              ca.station_type != messages::station_type::kRoadSideUnit;
  c.mqtt = vehicle == nullptr || vehicle->station_mqtt;
  if (vehicle && vehicle->station_kind == scenario::StationKind::kPooled)
    c.verify_policy = security::VerifyPolicy::kOnDemand;
  // LCRW computes in an East-North-Up frame; with a scenario it is anchored where the map's
  // (0, 0, 0) lies (the map's geoReference, or the scenario's origin: common/map's ScenarioMap).
  if (scenario)
    c.lcrw_origin = *map::ScenarioMap(*scenario).origin().origin;
  c.fix_period_s = 1.0 / (scenario ? scenario->rates.gnss_hz : 10.0);

  c.publisher = apps::mqtt::PublisherConfig{o.mqtt_prefix, station_id,
                                            std::chrono::milliseconds{o.mqtt_cam_interval_ms}};
  return c;
}

}  // namespace tb::its::station
