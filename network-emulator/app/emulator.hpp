#pragma once
/// @file Emulator: vehicle states in, each station's GNSS and CAN feeds out; signal states in,
/// each RSU's signal feed out (issue 34).
///
/// One GpsAgent and one CanFeeder per configured vehicle station. An RSU station has a GpsAgent
/// fed a stationary state at its site (common/map/rsu_site.hpp) with every state datagram, so
/// that its gpsd reports a fix like a vehicle's at the scenario's GNSS rate, no CAN feeder, and
/// a share of the SignalFeed. Everything that touches a socket
/// sits behind DatagramSink (NMEA) and tb::can::CanBus (CAN), made by an injected factory, so
/// that tests drive the emulator with byte strings and fake sinks.

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <system_error>
#include <unordered_map>
#include <vector>

#include "common/can/can_bus.hpp"
#include "common/can/dbc.hpp"
#include "common/clock/clock.hpp"
#include "common/map/rsu_site.hpp"
#include "common/map/scenario_map.hpp"
#include "common/scenario/scenario.hpp"
#include "common/trace/tracer.hpp"
#include "common/wire/vehicle_state.hpp"
#include "network-emulator/app/datagram_sink.hpp"
#include "network-emulator/app/peer_health.hpp"
#include "network-emulator/app/signal_feed.hpp"
#include "network-emulator/app/stations_config.hpp"
#include "network-emulator/can/can_feeder.hpp"
#include "network-emulator/gnss/gps_agent.hpp"
#include "network-emulator/gnss/world_start.hpp"

namespace tb::emu {

struct StationIo {
  StationIo() = default;
  StationIo(std::unique_ptr<DatagramSink> gnss_feed, std::unique_ptr<tb::can::CanBus> can_bus,
            std::unique_ptr<DatagramSink> signal_feed = nullptr)
      : gnss(std::move(gnss_feed)), can(std::move(can_bus)), signals(std::move(signal_feed)) {}
  std::unique_ptr<DatagramSink> gnss;
  std::unique_ptr<tb::can::CanBus> can;  ///< none for an RSU
  /// An RSU's signal feed (its address, signal_port); none for a vehicle.
  std::unique_ptr<DatagramSink> signals;
};
using StationIoFactory = std::function<StationIo(const StationEndpoints&)>;

struct Counters {
  std::uint64_t datagrams = 0;  ///< received
  std::uint64_t states = 0;     ///< decoded, for a configured station
  std::uint64_t malformed = 0;  ///< datagrams that did not decode (all their states dropped)
  std::array<std::uint64_t, wire::kDecodeErrorCount> malformed_by_error{};  ///< by DecodeError
  std::uint64_t unknown_station = 0;  ///< states decoded, but for no configured station
  std::uint64_t nmea_sent = 0, nmea_failed = 0, nmea_skipped = 0;
  std::uint64_t can_frames_sent = 0, can_failed = 0, can_skipped = 0;
  std::uint64_t rsu_states = 0;  ///< stationary states fed to the RSUs' GPS agents
};

class Emulator {
 public:
  /// @p scenario, @p dbc, @p clock and @p tracer must outlive the emulator.
  /// @throws std::runtime_error when the DBC cannot be fed (tb::emu::can::FeederError).
  Emulator(const scenario::Scenario& scenario, const tb::can::Database& dbc,
           const std::vector<StationEndpoints>& stations, const StationIoFactory& make_io,
           const clock::Clock& clock, trace::Tracer& tracer, std::uint64_t seed = 1);
  // The GPS agents refer to map_: the emulator stays where it was made.
  Emulator(const Emulator&) = delete;
  Emulator& operator=(const Emulator&) = delete;

  /// Handles one received batch datagram (docs/wire.md): each of its states in order. Returns
  /// whether it was valid (states of any station), which the program passes on to --forward
  /// receivers.
  bool handle_datagram(std::span<const std::uint8_t> bytes);
  /// Handles one signal-feed datagram (docs/wire.md, "Signal feed"): each RSU gets its
  /// junction's groups at once. Returns whether it was passed on (not malformed, not a copy).
  bool handle_signal_datagram(std::span<const std::uint8_t> bytes) {
    return signals_->handle_datagram(bytes);
  }
  const SignalFeedCounters& signal_counters() const { return signals_->counters(); }
  std::size_t rsu_count() const { return rsus_.size(); }

  const Counters& counters() const { return counters_; }
  std::size_t station_count() const { return stations_.size(); }
  /// Stations whose GNSS or CAN receiver is paused.
  std::size_t paused_stations() const;
  /// One line for the log: totals and stations paused.
  std::string status_line() const;

 private:
  struct Station {
    std::uint32_t id;
    StationEndpoints endpoints;
    gnss::GpsAgent gps;
    std::optional<can::CanFeeder> can;  ///< none for an RSU
    StationIo io;
    PeerHealth gnss_health;
    PeerHealth can_health;
    /// An RSU's state: where its antenna is, standing still; tick and times from the stream.
    std::optional<wire::VehicleState> fixed;
  };

  void handle_state(const wire::VehicleState& state);
  void feed_gps(Station& s, const wire::VehicleState& state);
  /// Feeds every RSU's GPS agent its stationary state at the time of @p newest.
  void feed_rsus(const wire::VehicleState& newest);
  void send_nmea(Station& s, const wire::VehicleState& state, std::string_view nmea);
  void send_can(Station& s, const wire::VehicleState& state,
                std::span<const tb::can::CanFrame> frames);
  void report(Station& s, const char* feed, PeerHealth::Change change, const PeerHealth& h);
  void add_rsu(const StationEndpoints& e, const scenario::Rsu& r, const map::RsuSite& site,
               const StationIoFactory& make_io, std::uint64_t seed,
               std::vector<SignalFeed::Rsu>& feed);
  std::string signal_status() const;

  const scenario::Scenario& scenario_;
  const clock::Clock& clock_;
  trace::Tracer& tracer_;
  /// Where the map's frame lies on the Earth (its geoReference, or the scenario's origin).
  map::ScenarioMap map_;
  std::unordered_map<std::uint32_t, std::unique_ptr<Station>> stations_;
  std::vector<Station*> rsus_;  ///< the RSU stations, in the stations' order
  std::unique_ptr<SignalFeed> signals_;
  Counters counters_;
  std::vector<wire::VehicleState> batch_;  ///< the datagram being handled; capacity reused
  std::array<bool, wire::kDecodeErrorCount> logged_malformed_{};
  bool logged_unknown_ = false;
  /// The world's start time the agents date fixes from; empty until a batch names one (or, for
  /// batches that do not, the scenario's pinned start_time stands in).
  WorldStart world_start_;
};

}  // namespace tb::emu
