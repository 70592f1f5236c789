#pragma once
/// @file The server's side of the sim protocol for every connected client, without sockets.
///
/// The Hub turns client bytes into attachments and controls of the World's vehicles and the
/// World's states into one shared State frame per step. Sockets live behind ClientLink
/// (tcp_server.hpp in the program, a fake in the tests); time comes from a clock::Clock.
///
/// Safety rules (issue 3): a malformed, oversized or out-of-order message closes only that
/// client; a vehicle whose driver leaves or is silent for more than kDriverTimeout brakes to a
/// stop; a second driver for a vehicle is refused with a reason; out-of-range controls are
/// clamped and counted; a client whose send queue is full is dropped.

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "common/clock/clock.hpp"
#include "common/scenario/scenario.hpp"
#include "common/wire/sim_protocol.hpp"
#include "sim-server/physics/world.hpp"
#include "sim-server/signals/signal_set.hpp"

namespace tb::server {

using Bytes = std::vector<std::uint8_t>;
using SharedBytes = std::shared_ptr<const Bytes>;

/// What a frame is to the slow-client rule.
enum class FrameKind {
  /// An answer or an announcement (Welcome, AttachResult, DriverChanged, Closing): always
  /// queued, since their number is bounded by what the clients ask. A scripted client that
  /// claims 300 vehicles in one go gets 600 of them at once (answer and announcement each).
  kReply,
  /// The periodic world state: refused when the client already has its limit of them queued,
  /// which is how a client that does not keep up is found.
  kState,
};

/// One client's byte stream towards it.
class ClientLink {
 public:
  virtual ~ClientLink() = default;
  /// Queues a frame without blocking; false when a kState frame finds the queue full.
  virtual bool send(SharedBytes frame, FrameKind kind) = 0;
  /// Sends what is queued (best effort), then closes. The link must not call back into the hub
  /// from here.
  virtual void close() = 0;
};

struct HubStats {
  std::uint64_t connections = 0;
  std::uint64_t protocol_errors = 0;  ///< connections closed for bad input
  std::uint64_t slow_drops = 0;       ///< connections closed because their queue was full
  std::uint64_t clamped_values = 0;   ///< control values outside their range, clamped
  std::uint64_t watchdog_stops = 0;   ///< vehicles braked because their driver fell silent
  std::uint64_t frames_sent = 0;      ///< State frames queued, over all clients
};

class Hub {
 public:
  using ClientId = std::uint64_t;
  /// Silence after which a driven vehicle brakes to a stop (issue 3).
  static constexpr std::chrono::milliseconds kDriverTimeout{500};
  /// Brake pedal of a vehicle nobody drives: a firm stop (about 6 m/s²) that following traffic
  /// can react to, rather than an emergency stop.
  static constexpr float kStopBrake = 0.5f;

  /// @p scenario_json is the scenario file's text, sent to clients in Welcome with the
  /// scenario's OpenDRIVE text (Scenario::map_text).
  Hub(physics::World& world, const scenario::Scenario& scenario, std::string scenario_json,
      const clock::Clock& clock, std::string server_name = "sim-server");

  /// A new connection; @p peer names it in logs. The link must outlive the client's id.
  ClientId connect(ClientLink& link, std::string peer);
  /// Bytes the client sent. May close the client (its link's close() is called, the id is
  /// forgotten).
  void receive(ClientId id, std::span<const std::uint8_t> bytes);
  /// The connection is gone (peer closed, I/O error). Unknown ids are ignored.
  void disconnect(ClientId id);

  /// Before each physics step: vehicles without a live driver get brake-to-stop controls.
  void before_step();
  /// After each physics step: the traffic lights evaluated at the step's world time, the State
  /// frame to every attached client, and SignalStates when a light changed or a second passed.
  void after_step();
  /// SignalStates go out at least this often (and in every step where a light changes).
  static constexpr std::int64_t kSignalStatesPeriodMs = 1000;
  /// The traffic lights as of the latest step (issue 34).
  const SignalSet& signals() const { return signals_; }
  /// UTC of sim time 0, Unix ns: fixed when the hub was made (scenario::world_start()).
  std::int64_t world_start_ns() const { return world_start_ns_; }
  /// Whether the driver of every driven vehicle has answered the latest State frame with
  /// Controls (a vehicle braked by the watchdog is not waited for). Fast mode steps only then,
  /// so that scripted drivers see every state as they do in real time.
  bool drivers_answered() const;
  /// Called when a driver attaches, or answers the latest State frame as the last one to.
  void on_drivers_changed(std::function<void()> f) { changed_ = std::move(f); }
  /// Sends Closing(@p reason) to everyone and closes every link: kScenarioFinished when the
  /// scenario's duration is over (clients stop), kShutdown otherwise (clients reconnect).
  void shutdown(std::string_view why,
                wire::sim::CloseReason reason = wire::sim::CloseReason::kShutdown);

  const HubStats& stats() const { return stats_; }
  std::size_t clients() const { return clients_.size(); }
  /// The id of the client driving @p vehicle, or 0.
  ClientId driver_of(std::size_t vehicle) const { return vehicles_.at(vehicle).driver; }
  /// Ids of the vehicles whose scenario driver is a script (timeline, lane_follow) and that
  /// nobody drives yet: the physics waits for them (SimLoop), since their scripts and their
  /// states' way to the GPS agents both come with the client that drives them.
  std::vector<std::string> scripted_without_driver() const;

 private:
  struct Client {
    ClientLink* link = nullptr;
    std::string peer;
    std::string name;
    wire::sim::FrameParser parser{wire::sim::Sender::kClient};
    wire::sim::Conversation conversation;
    bool streaming = false;           ///< attached as watcher or driver
    clock::SteadyTime last_attach{};  ///< its latest successful driver Attach
  };
  struct VehicleSlot {
    ClientId driver = 0;
    clock::SteadyTime last_controls{};
    bool stopping = true;  ///< brake-to-stop in force
    std::uint16_t lights = 0;
    /// Input time (Controls.input_ns, else the arrival) of controls not yet applied in a step,
    /// or 0; and their arrival.
    std::int64_t input_ns = 0;
    std::int64_t arrival_ns = 0;
    std::uint64_t answered = 0;  ///< frames_ when its latest controls came
  };

  void handle(ClientId id, Client& c, const wire::sim::ClientMessage& m);
  void attach(ClientId id, Client& c, const wire::sim::Attach& a);
  /// Applies one vehicle's controls (a Controls or a batch entry) that arrived at @p now;
  /// true when they answer the latest State frame for that vehicle for the first time.
  bool apply(ClientId id, const Client& c, const wire::sim::ControlsMsg& in, clock::SteadyTime now,
             std::int64_t arrival_ns);
  void release(std::size_t vehicle, std::string_view why);
  void close_client(ClientId id, wire::sim::CloseReason reason, const std::string& text);
  void broadcast(const SharedBytes& frame, FrameKind kind);
  void stop_vehicle(std::size_t vehicle);
  wire::sim::Welcome welcome() const;
  /// The step's world time, UTC Unix ms (start time + sim time).
  std::int64_t world_time_ms() const;
  std::string label(const Client& c) const;

  physics::World& world_;
  const scenario::Scenario& scenario_;
  std::string scenario_json_;
  const clock::Clock& clock_;
  std::string server_name_;
  std::int64_t world_start_ns_ = 0;  ///< Unix ns of sim time 0 (Welcome, docs/time.md)
  SignalSet signals_;
  std::int64_t signals_sent_ms_ = 0;  ///< world time of the last SignalStates broadcast
  std::map<ClientId, Client> clients_;
  std::vector<VehicleSlot> vehicles_;
  ClientId next_id_ = 1;
  HubStats stats_;
  std::uint64_t frames_ = 0;  ///< State frames sent
  std::function<void()> changed_;
};

}  // namespace tb::server
