#pragma once
/// @file What one frame of the 3D view draws: plain data that the program's thread assembles
/// and the render thread reads (no OpenSceneGraph types, so that the program side needs none).

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/geodesy/local_frame.hpp"
#include "common/map/opendrive/road_network.hpp"
#include "common/wire/sim_protocol.hpp"
#include "common/wire/vehicle_state.hpp"
#include "sim-client/v2x/monitor.hpp"

namespace tb::client::view3d {

enum class CameraMode : std::uint8_t { kChase, kCockpit, kTop, kOrbit };
inline constexpr int kCameraModes = 4;
std::string_view to_string(CameraMode m);
/// "chase", "cockpit" (also "hood"), "top", "orbit".
std::optional<CameraMode> parse_camera(std::string_view text);

/// A vehicle's looks, from the server's Welcome (the scenario's vehicle model and colour).
struct VehicleLook {
  std::string id;
  std::uint32_t station_id = 0;
  std::array<float, 3> colour{0.8f, 0.8f, 0.8f};  ///< RGB, 0..1
  float length_m = 4.5f, width_m = 1.8f, height_m = 1.45f;
  float wheelbase_m = 2.6f, track_m = 1.54f, wheel_radius_m = 0.32f;
  bool operator==(const VehicleLook&) const = default;
};

/// The world: what changes only with a new Welcome.
struct World {
  std::shared_ptr<const map::odr::RoadNetwork> network;
  std::vector<VehicleLook> vehicles;  ///< Welcome order
  /// Where WGS84 positions (DENM events) land in the local frame; empty: not drawn.
  std::optional<geodesy::LocalFrame> frame;
  /// How far a station's frames reach under the scenario's channel model
  /// (scenario::max_range_m, what the radio medium enforces); empty: the ideal channel, no limit.
  std::optional<double> radio_range_m;
  std::uint64_t version = 0;  ///< changes whenever anything above does
};

/// What the keys and the mouse chose (view_controls.hpp).
struct ViewChoice {
  CameraMode camera = CameraMode::kChase;
  int target = -1;  ///< vehicle picked with [ ] (Welcome index); -1: the own car, else the first
  bool overlay = false;               ///< the V2X network over the world
  bool show_fps = false;              ///< frame rate line
  bool help = false;                  ///< key map
  double orbit_azimuth_deg = -135.0;  ///< from east, counter-clockwise
  double orbit_elevation_deg = 30.0;
  double orbit_distance_m = 40.0;
  double top_zoom = 1.0;   ///< top camera: 8 px/m times this
  double hfov_deg = 90.0;  ///< horizontal field of view of the perspective cameras
};

/// The HUD's text that is not in a vehicle state.
struct HudStatus {
  std::string connection;  ///< "connected to …", "retrying …"
  std::string input;       ///< "keyboard", "controller …"
  std::string mqtt;        ///< empty without --mqtt
  bool watching = false;   ///< no vehicle driven by this client's input
  bool finished = false;   ///< the server said the scenario finished: the window waits to close
};

struct FrameInput {
  std::shared_ptr<const World> world;
  std::vector<wire::VehicleState> vehicles;  ///< interpolated, Welcome order
  std::int64_t sim_time_ns = 0;
  /// The traffic lights: every junction's signal groups as the latest SignalStates gave them.
  std::vector<wire::sim::SignalGroupState> signals;
  int own = -1;  ///< the vehicle this client's input drives; -1 when watching
  ViewChoice choice;
  HudStatus status;
  v2x::V2xPicture v2x;
  bool v2x_enabled = false;  ///< --mqtt given
  double fps = 0.0;          ///< measured frame rate
};

}  // namespace tb::client::view3d
