#include "sim-server/server/hub.hpp"

#include <spdlog/spdlog.h>

#include <cmath>
#include <numbers>

#include "common/trace/tracer.hpp"

namespace tb::server {

namespace sim = wire::sim;

namespace {

SharedBytes share(Bytes b) {
  return std::make_shared<const Bytes>(std::move(b));
}

sim::DriverKind kind_of(const scenario::Driver& d) {
  if (std::holds_alternative<scenario::TimelineDriver>(d))
    return sim::DriverKind::kTimeline;
  if (std::holds_alternative<scenario::LaneFollowDriver>(d))
    return sim::DriverKind::kLaneFollow;
  return sim::DriverKind::kHuman;
}

}  // namespace

Hub::Hub(physics::World& world, const scenario::Scenario& scenario, std::string scenario_json,
         const clock::Clock& clock, std::string server_name)
    : world_(world),
      scenario_(scenario),
      scenario_json_(std::move(scenario_json)),
      clock_(clock),
      server_name_(std::move(server_name)),
      // Sim time runs from -warmup_s: sim time 0 comes a warm-up after the start, so that the
      // world's time is the host's from then on (less the wait for the drivers, if any).
      world_start_ns_(clock::to_unix_ns(scenario::world_start(
          scenario, clock.wall_now() + std::chrono::duration_cast<clock::WallClock::duration>(
                                           std::chrono::duration<double>(scenario.warmup_s))))),
      signals_(scenario.signals, world_start_ns_ / 1'000'000),
      vehicles_(world.size()) {
  // The lights as of the world's present (the first warm-up step), for the first Welcome.
  signals_.step(world_time_ms());
  for (std::size_t v = 0; v < vehicles_.size(); ++v) {
    // A car spawned with speed rolls on until before_step() finds nobody drives it.
    vehicles_[v].lights = world_.states()[v].lights;
  }
}

std::string Hub::label(const Client& c) const {
  return c.name.empty() ? c.peer : fmt::format("'{}' ({})", c.name, c.peer);
}

Hub::ClientId Hub::connect(ClientLink& link, std::string peer) {
  const ClientId id = next_id_++;
  Client& c = clients_[id];
  c.link = &link;
  c.peer = std::move(peer);
  ++stats_.connections;
  spdlog::info("client {} connected from {}", id, c.peer);
  return id;
}

void Hub::receive(ClientId id, std::span<const std::uint8_t> bytes) {
  while (!bytes.empty()) {
    auto it = clients_.find(id);
    if (it == clients_.end())
      return;
    Client& c = it->second;
    auto r = c.parser.parse(bytes);
    if (!r) {
      close_client(id, sim::CloseReason::kProtocolError,
                   fmt::format("bad frame: {}", sim::to_string(r.error())));
      return;
    }
    if (*r == sim::FrameParser::Status::kNeedMore)
      return;
    const sim::Frame& f = c.parser.frame();
    auto m = sim::decode_client(f);
    if (!m) {
      close_client(
          id, sim::CloseReason::kProtocolError,
          fmt::format("malformed {}: {}", sim::to_string(f.type), sim::to_string(m.error())));
      return;
    }
    if (auto ok = c.conversation.check(*m); !ok) {
      close_client(id, sim::CloseReason::kProtocolError,
                   fmt::format("{} {}", sim::to_string(f.type), sim::to_string(ok.error())));
      return;
    }
    handle(id, c, *m);
  }
}

void Hub::handle(ClientId id, Client& c, const sim::ClientMessage& m) {
  if (const auto* hello = std::get_if<sim::Hello>(&m)) {
    c.name = hello->client_name;
    c.conversation.on_hello();
    spdlog::info("client {} is {}", id, label(c));
    c.link->send(share(sim::encode(welcome())), FrameKind::kReply);
    // The lights right away, so that a new client need not wait for the next change.
    if (!signals_.empty())
      c.link->send(share(sim::encode(signals_.latest())), FrameKind::kReply);
  } else if (const auto* a = std::get_if<sim::Attach>(&m)) {
    attach(id, c, *a);
  } else if (const auto* in = std::get_if<sim::ControlsMsg>(&m)) {
    const bool waited =
        apply(id, c, *in, clock_.steady_now(), clock::to_unix_ns(clock_.wall_now()));
    if (waited && changed_ && drivers_answered())
      changed_();
  } else if (const auto* b = std::get_if<sim::ControlsBatch>(&m)) {
    // One clock reading and one look at the other drivers for the whole batch: it is one
    // instant of the client's.
    const auto now = clock_.steady_now();
    const std::int64_t arrival_ns = clock::to_unix_ns(clock_.wall_now());
    bool waited = false;
    for (const sim::ControlsMsg& e : b->entries)
      waited = apply(id, c, e, now, arrival_ns) || waited;
    if (waited && changed_ && drivers_answered())
      changed_();
  } else if (const auto* d = std::get_if<sim::Detach>(&m)) {
    c.conversation.on_released(d->vehicle);
    release(d->vehicle, fmt::format("detached by {}", label(c)));
  }
}

bool Hub::apply(ClientId id, const Client& c, const sim::ControlsMsg& in, clock::SteadyTime now,
                std::int64_t arrival_ns) {
  wire::Controls controls = in.controls;
  if (const int n = sim::clamp(controls); n > 0) {
    stats_.clamped_values += static_cast<std::uint64_t>(n);
    spdlog::debug("client {}: {} control value(s) clamped for vehicle {}", id, n, in.vehicle);
  }
  VehicleSlot& slot = vehicles_[in.vehicle];
  if (slot.stopping)
    spdlog::info("vehicle {} driven again by {}", scenario_.vehicles[in.vehicle].id, label(c));
  slot.stopping = false;
  slot.last_controls = now;
  // t1 (docs/tracing.md) runs from the client's input sample to the step that applies it;
  // a client that does not know when its input was read sends 0: then from the arrival.
  slot.arrival_ns = arrival_ns;
  slot.input_ns = in.input_ns != 0 ? in.input_ns : arrival_ns;
  slot.lights = in.lights;
  world_.set_controls(in.vehicle, controls, in.lights);
  const bool waited = slot.answered < frames_;
  slot.answered = frames_;
  return waited;
}

void Hub::attach(ClientId id, Client& c, const sim::Attach& a) {
  sim::AttachResult res{a.role, a.vehicle, sim::AttachStatus::kOk, ""};
  if (a.role == sim::Role::kWatcher) {
    c.streaming = true;
    spdlog::info("client {} watches", label(c));
    c.link->send(share(sim::encode(res)), FrameKind::kReply);
    return;
  }
  if (a.vehicle >= vehicles_.size()) {
    res.status = sim::AttachStatus::kUnknownVehicle;
    res.reason = fmt::format("no vehicle {} (the scenario has {})", a.vehicle, vehicles_.size());
  } else if (const ClientId other = vehicles_[a.vehicle].driver; other != 0 && other != id) {
    res.status = sim::AttachStatus::kAlreadyDriven;
    res.reason = fmt::format("vehicle '{}' is driven by {}", scenario_.vehicles[a.vehicle].id,
                             label(clients_.at(other)));
  }
  if (res.status != sim::AttachStatus::kOk) {
    spdlog::info("client {}: attach to vehicle {} refused: {}", label(c), a.vehicle, res.reason);
    c.link->send(share(sim::encode(res)), FrameKind::kReply);
    return;
  }
  VehicleSlot& slot = vehicles_[a.vehicle];
  const bool changed = slot.driver != id;
  slot.driver = id;
  // The watchdog runs from the attachment: a driver that never sends controls is silent too.
  slot.last_controls = clock_.steady_now();
  c.last_attach = slot.last_controls;
  c.conversation.on_driving(a.vehicle);
  c.streaming = true;
  spdlog::info("client {} drives vehicle '{}'", label(c), scenario_.vehicles[a.vehicle].id);
  c.link->send(share(sim::encode(res)), FrameKind::kReply);
  if (changed)
    broadcast(share(sim::encode(sim::DriverChanged{a.vehicle, c.name})), FrameKind::kReply);
  if (changed_)
    changed_();
}

void Hub::release(std::size_t vehicle, std::string_view why) {
  VehicleSlot& slot = vehicles_[vehicle];
  if (slot.driver == 0)
    return;
  slot.driver = 0;
  spdlog::info("vehicle '{}' has no driver ({}): braking to a stop", scenario_.vehicles[vehicle].id,
               why);
  stop_vehicle(vehicle);
  broadcast(share(sim::encode(sim::DriverChanged{static_cast<std::uint16_t>(vehicle), ""})),
            FrameKind::kReply);
}

void Hub::stop_vehicle(std::size_t vehicle) {
  VehicleSlot& slot = vehicles_[vehicle];
  slot.stopping = true;
  wire::Controls c = world_.controls(vehicle);
  // Keep the steering: straightening the wheels mid-curve would steer off the road.
  c.throttle = 0.0f;
  c.brake = kStopBrake;
  c.handbrake = false;
  world_.set_controls(vehicle, c, slot.lights | wire::kHazard);
}

void Hub::before_step() {
  const auto now = clock_.steady_now();
  auto& tracer = trace::global();
  const bool tracing = tracer.enabled();
  for (std::size_t v = 0; v < vehicles_.size(); ++v) {
    VehicleSlot& slot = vehicles_[v];
    if (slot.input_ns != 0 && tracing) {
      // End of t1 (docs/tracing.md): the latest controls go into the coming step.
      tracer.record("server.controls", {{"station", world_.states()[v].station_id},
                                        {"tick", world_.tick() + 1},
                                        {"input_ns", slot.input_ns},
                                        {"arrival_ns", slot.arrival_ns}});
    }
    slot.input_ns = 0;
    if (slot.stopping) {
      // Also covers cars nobody has driven yet; re-applied in case set_controls was bypassed.
      if (world_.controls(v).brake < kStopBrake)
        stop_vehicle(v);
      continue;
    }
    // A driver that has answered the latest State frame is not silent, however long ago that
    // was (fast mode waits for the others).
    if (slot.driver != 0 && slot.answered < frames_ && now - slot.last_controls > kDriverTimeout) {
      const auto it = clients_.find(slot.driver);
      // A client attaching many vehicles (a scripted client takes 1000 in one go) answers for
      // none of them before it has the last: its silence counts from its latest attachment.
      if (it != clients_.end() && now - it->second.last_attach <= kDriverTimeout)
        continue;
      ++stats_.watchdog_stops;
      spdlog::warn(
          "vehicle '{}': no controls from {} for {} ms: braking to a stop",
          scenario_.vehicles[v].id, it == clients_.end() ? "?" : label(it->second),
          std::chrono::duration_cast<std::chrono::milliseconds>(now - slot.last_controls).count());
      stop_vehicle(v);
    }
  }
}

std::int64_t Hub::world_time_ms() const {
  const std::int64_t ns = world_start_ns_ + world_.sim_time_ns();
  return ns >= 0 ? ns / 1'000'000 : -((-ns + 999'999) / 1'000'000);
}

void Hub::after_step() {
  const std::int64_t now_ms = world_time_ms();
  const auto changed = signals_.step(now_ms);
  if (!changed.empty()) {
    auto& tracer = trace::global();
    for (const sim::SignalGroupState& g : changed) {
      spdlog::debug("junction {} signal group {}: {} until {}", g.intersection_id, g.signal_group,
                    sim::to_string(g.state), g.next_change_ms);
      // Start of the light's way to the driver's HUD (issue 34's latency figure).
      if (tracer.enabled()) {
        tracer.record("server.signal", {{"intersection", g.intersection_id},
                                        {"group", g.signal_group},
                                        {"state", static_cast<int>(g.state)},
                                        {"world_ms", now_ms},
                                        {"next_change_ms", g.next_change_ms}});
      }
    }
  }
  bool any = false;
  for (const auto& [id, c] : clients_)
    any = any || c.streaming;
  if (!any)
    return;
  const auto states = world_.states();
  ++frames_;
  broadcast(share(sim::encode_state(world_.tick(), world_.sim_time_ns(),
                                    states.empty() ? 0 : states.front().step_wall_ns, states,
                                    clock::to_unix_ns(clock_.wall_now()))),
            FrameKind::kState);
  // After the state of the same step: a client sees where the cars were when the light changed.
  if (!signals_.empty() &&
      (!changed.empty() || now_ms - signals_sent_ms_ >= kSignalStatesPeriodMs)) {
    broadcast(share(sim::encode(signals_.latest())), FrameKind::kReply);
    signals_sent_ms_ = now_ms;
  }
}

bool Hub::drivers_answered() const {
  for (const VehicleSlot& slot : vehicles_) {
    if (slot.driver != 0 && !slot.stopping && slot.answered < frames_)
      return false;
  }
  return true;
}

void Hub::broadcast(const SharedBytes& frame, FrameKind kind) {
  std::vector<ClientId> slow;
  for (auto& [id, c] : clients_) {
    if (!c.streaming)
      continue;
    if (c.link->send(frame, kind))
      ++stats_.frames_sent;
    else
      slow.push_back(id);
  }
  for (ClientId id : slow) {
    ++stats_.slow_drops;
    close_client(id, sim::CloseReason::kTooSlow, "send queue full: the client reads too slowly");
  }
}

void Hub::close_client(ClientId id, sim::CloseReason reason, const std::string& text) {
  auto it = clients_.find(id);
  if (it == clients_.end())
    return;
  Client& c = it->second;
  if (reason == sim::CloseReason::kProtocolError)
    ++stats_.protocol_errors;
  if (reason != sim::CloseReason::kShutdown && reason != sim::CloseReason::kScenarioFinished) {
    spdlog::warn("client {} ({}): closing: {}", id, label(c), text);
  } else {
    spdlog::info("client {} ({}): closing: {}", id, label(c), text);
  }
  // Best effort: a full queue refuses this too, and the connection closes without it.
  c.link->send(share(sim::encode(sim::Closing{reason, text})), FrameKind::kReply);
  c.link->close();
  disconnect(id);
}

void Hub::disconnect(ClientId id) {
  auto it = clients_.find(id);
  if (it == clients_.end())
    return;
  const std::string who = label(it->second);
  clients_.erase(it);
  spdlog::info("client {} ({}) gone", id, who);
  for (std::size_t v = 0; v < vehicles_.size(); ++v) {
    if (vehicles_[v].driver == id)
      release(v, fmt::format("{} disconnected", who));
  }
}

std::vector<std::string> Hub::scripted_without_driver() const {
  std::vector<std::string> out;
  for (std::size_t v = 0; v < vehicles_.size() && v < scenario_.vehicles.size(); ++v) {
    if (vehicles_[v].driver == 0 &&
        kind_of(scenario_.vehicles[v].driver) != sim::DriverKind::kHuman)
      out.push_back(scenario_.vehicles[v].id);
  }
  return out;
}

void Hub::shutdown(std::string_view why, sim::CloseReason reason) {
  while (!clients_.empty())
    close_client(clients_.begin()->first, reason, std::string(why));
}

sim::Welcome Hub::welcome() const {
  sim::Welcome w;
  w.server_name = server_name_;
  w.step_ns = std::llround(world_.step_s() * 1e9);
  w.world_start_ns = world_start_ns_;
  w.scenario_json = scenario_json_;
  if (scenario_.map_text)
    w.map_text = *scenario_.map_text;
  for (std::size_t i = 0; i < scenario_.vehicles.size() && i < vehicles_.size(); ++i) {
    const auto& v = scenario_.vehicles[i];
    sim::VehicleInfo info;
    info.index = static_cast<std::uint16_t>(i);
    info.id = v.id;
    info.station_id = v.station_id;
    info.station_type = static_cast<std::uint8_t>(v.station_type);
    info.color = v.color;
    info.driver_kind = kind_of(v.driver);
    info.length_m = static_cast<float>(v.model.length_m);
    info.width_m = static_cast<float>(v.model.width_m);
    info.height_m = static_cast<float>(v.model.height_m);
    info.wheelbase_m = static_cast<float>(v.model.wheelbase_m);
    info.track_m = static_cast<float>(v.model.track_m);
    info.wheel_radius_m = static_cast<float>(v.model.wheel_radius_m);
    info.max_steer_rad = static_cast<float>(v.model.max_steer_deg * std::numbers::pi / 180.0);
    if (const ClientId d = vehicles_[i].driver; d != 0)
      info.driver = clients_.at(d).name;
    w.vehicles.push_back(std::move(info));
  }
  return w;
}

}  // namespace tb::server
