#pragma once
/// @file The client side of the sim-server protocol (sim-server/PROTOCOL.md) as pure logic:
/// bytes in, bytes out through a callback, no socket and no clock of its own. TcpLink
/// (tcp_link.hpp) carries the bytes; tests feed them by hand.

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "common/clock/clock.hpp"
#include "common/map/opendrive/road_network.hpp"
#include "common/map/scenario_map.hpp"
#include "common/scenario/scenario.hpp"
#include "common/trace/tracer.hpp"
#include "common/wire/sim_protocol.hpp"
#include "sim-client/driver/scripted_driver.hpp"
#include "sim-client/input/command.hpp"
#include "sim-client/net/forwarder.hpp"

namespace tb::client {

struct SessionOptions {
  std::string client_name = "sim-client";
  std::vector<std::string> vehicles;  ///< scenario ids to drive (--vehicle)
  bool scripted = false;              ///< also drive every vehicle with a scripted driver
  bool list_only = false;             ///< stop after Welcome (--list)
  /// Reconnect even after the server said the scenario finished (--reconnect: the server may
  /// be restarted with the next run); otherwise the session ends there (Phase::kFinished).
  bool reconnect = false;
  /// Also forward the states of the vehicles nobody drives (--forward-undriven): a human car
  /// before its driver connects or after they left (braking to a stop) keeps feeding its
  /// station, which would otherwise keep its last fix. Until a DriverChanged names a driver.
  bool forward_undriven = false;
};

/// One line per vehicle: index, id, station id, scenario driver, who drives it now.
std::string format_vehicle_list(const wire::sim::Welcome& w);

class SimSession {
 public:
  using Send = std::function<void(std::vector<std::uint8_t>)>;

  enum class Phase {
    kDisconnected,
    kGreeting,  ///< Hello sent, waiting for Welcome
    kRunning,   ///< attached (or watching), state stream flowing
    kListed,    ///< --list: Welcome received, nothing more to do
    kFinished,  ///< the server said the scenario finished (Closing): nothing more will come
    kFailed,    ///< cannot go on (see fatal_error()); the program exits non-zero
  };

  /// @p forwarder may be null (no forwarding, as with --list). @p clock dates the scripted
  /// drivers' input (the state they read) for Controls.input_ns; the system clock by default.
  SimSession(SessionOptions options, Send send, StateForwarder* forwarder,
             trace::Tracer& tracer = trace::global(), const clock::Clock* clock = nullptr);

  void on_connected();
  /// Feeds bytes from the server. Returns false when the connection must be closed: a
  /// protocol error (last_error() names it), Closing from the server, or a fatal error.
  /// Closing(scenario finished) ends the session (kFinished) unless options.reconnect.
  bool on_bytes(std::span<const std::uint8_t> bytes);
  void on_disconnected();

  /// The human driver's latest command and when the controller was read for it
  /// (CLOCK_REALTIME); sent for the human-driven vehicles every tick, with that time as
  /// Controls.input_ns (the start of t1, docs/tracing.md).
  void set_human_command(const DriverCommand& c, clock::WallTime sampled) {
    human_ = c;
    human_sampled_ns_ = clock::to_unix_ns(sampled);
  }

  Phase phase() const { return phase_; }
  /// True once a Welcome arrived on this connection (the link resets its backoff then).
  bool welcomed() const { return phase_ == Phase::kRunning || phase_ == Phase::kListed; }
  /// Whether the session is over for good (listed, finished, failed): the link stops rather
  /// than reconnects.
  bool ended() const {
    return phase_ == Phase::kListed || phase_ == Phase::kFinished || phase_ == Phase::kFailed;
  }
  const std::string& fatal_error() const { return fatal_; }
  const std::string& last_error() const { return last_error_; }

  // What the view draws.
  const wire::sim::Welcome* welcome() const { return welcome_ ? &*welcome_ : nullptr; }
  const scenario::Scenario* scenario() const { return scenario_ ? &*scenario_ : nullptr; }
  /// The world's map (common/map's one model: network, lane locator and graph, WGS84), built
  /// from the scenario and map text of the server's Welcome.
  const map::ScenarioMap* map() const { return map_.get(); }
  std::shared_ptr<const map::ScenarioMap> shared_map() const { return map_; }
  /// The world's road network: what drivers and views read.
  const map::odr::RoadNetwork* network() const { return map_ ? &map_->network() : nullptr; }
  /// The same, shared: a view on another thread keeps it while the session moves on to a new
  /// world.
  std::shared_ptr<const map::odr::RoadNetwork> shared_network() const {
    return map_ ? std::shared_ptr<const map::odr::RoadNetwork>(map_, &map_->network()) : nullptr;
  }
  const wire::sim::StateFrame* latest() const { return latest_ ? &*latest_ : nullptr; }
  /// One junction's traffic lights as the latest SignalStates gave them (issue 34).
  struct JunctionSignals {
    std::int64_t world_time_ms = 0;                   ///< of the step the states are from
    std::vector<wire::sim::SignalGroupState> groups;  ///< ascending by signal group
  };
  /// The latest signal states by IntersectionID (the OpenDRIVE junction id), for the views.
  const std::map<std::uint16_t, JunctionSignals>& signals() const { return signals_; }
  /// The same as the scripted drivers read them (each state frame's Traffic points here).
  const TrafficLights& lights() const { return lights_; }
  /// How many SignalStates arrived (on any connection): a view copies them when it changes.
  std::uint64_t signal_updates() const { return signal_updates_; }
  /// Every junction's groups of the latest SignalStates, ascending by (intersection, group).
  std::vector<wire::sim::SignalGroupState> signal_groups() const;
  /// Indices (Welcome order) of the vehicles this connection drives.
  std::vector<std::uint16_t> driven() const;
  /// Whether the vehicle at @p index is driven by the human input (not a script).
  bool human_driven(std::uint16_t index) const;
  std::uint64_t frames() const { return frames_; }
  /// Called with every state frame as it arrives, after its states were forwarded and its
  /// controls sent (the 3D view times arrivals for its interpolation).
  void set_frame_observer(std::function<void(const wire::sim::StateFrame&)> f) {
    frame_observer_ = std::move(f);
  }
  /// Where every SignalStates goes on to the emulator (issue 34); null: nowhere. Set on the
  /// clients that forward vehicle states.
  void set_signal_forwarder(SignalForwarder* f) { signal_forwarder_ = f; }

 private:
  struct Driven {
    std::uint16_t index = 0;
    std::uint32_t station_id = 0;
    bool attached = false;
    bool answered = false;
    bool ever_attached = false;  ///< on an earlier connection: a refusal now may be our old one
    std::unique_ptr<ScriptedDriver> script;  ///< null: the human input drives
    std::uint16_t lights = 0;  ///< a scripted vehicle's light switches (the scenario's "lights")
    std::uint64_t seq = 0;
  };

  bool handle(const wire::sim::ServerMessage& m);
  bool on_welcome(const wire::sim::Welcome& w);
  void on_attach_result(const wire::sim::AttachResult& r);
  void on_state(const wire::sim::StateFrame& f);
  void fail(std::string why);

  SessionOptions options_;
  Send send_;
  StateForwarder* forwarder_;
  SignalForwarder* signal_forwarder_ = nullptr;
  std::vector<wire::VehicleState> tick_states_;  ///< the driven vehicles' states of one frame
  wire::sim::ControlsBatch batch_;               ///< the driven vehicles' controls of one frame
  trace::Tracer& tracer_;
  Phase phase_ = Phase::kDisconnected;
  wire::sim::FrameParser parser_{wire::sim::Sender::kServer};
  std::optional<wire::sim::Welcome> welcome_;
  std::optional<scenario::Scenario> scenario_;
  std::shared_ptr<const map::ScenarioMap> map_;
  std::unique_ptr<DriveMap> drive_map_;  ///< what the scripted drivers share about the map
  std::vector<VehicleSize> sizes_;       ///< of the scenario's vehicles, for Traffic
  std::optional<wire::sim::StateFrame> latest_;
  std::map<std::uint16_t, JunctionSignals> signals_;
  TrafficLights lights_;
  std::uint64_t signal_updates_ = 0;
  std::map<std::uint16_t, Driven> driven_;
  DriverCommand human_;
  std::int64_t human_sampled_ns_ = 0;
  const clock::Clock* clock_;
  std::string fatal_;
  std::string last_error_;
  std::uint64_t frames_ = 0;
  std::function<void(const wire::sim::StateFrame&)> frame_observer_;
};

std::string_view to_string(SimSession::Phase p);

}  // namespace tb::client
