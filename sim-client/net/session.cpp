#include "sim-client/net/session.hpp"

#include <algorithm>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "common/scenario/loader.hpp"

namespace tb::client {

namespace sim = wire::sim;

namespace {

std::string_view driver_kind(sim::DriverKind k) {
  switch (k) {
    case sim::DriverKind::kHuman:
      return "human";
    case sim::DriverKind::kTimeline:
      return "timeline";
    case sim::DriverKind::kLaneFollow:
      return "lane_follow";
  }
  return "?";
}

}  // namespace

std::vector<sim::SignalGroupState> SimSession::signal_groups() const {
  std::vector<sim::SignalGroupState> out;
  for (const auto& [id, j] : signals_)
    out.insert(out.end(), j.groups.begin(), j.groups.end());
  return out;
}

std::string_view to_string(SimSession::Phase p) {
  switch (p) {
    case SimSession::Phase::kDisconnected:
      return "disconnected";
    case SimSession::Phase::kGreeting:
      return "connecting";
    case SimSession::Phase::kRunning:
      return "connected";
    case SimSession::Phase::kListed:
      return "listed";
    case SimSession::Phase::kFinished:
      return "scenario finished";
    case SimSession::Phase::kFailed:
      return "failed";
  }
  return "?";
}

std::string format_vehicle_list(const sim::Welcome& w) {
  std::string out = fmt::format("{:>5}  {:<16} {:>10}  {:<12} {}\n", "index", "id", "station",
                                "driver", "driven by");
  for (const auto& v : w.vehicles) {
    out += fmt::format("{:>5}  {:<16} {:>10}  {:<12} {}\n", v.index, v.id, v.station_id,
                       driver_kind(v.driver_kind), v.driver.empty() ? "-" : v.driver);
  }
  return out;
}

SimSession::SimSession(SessionOptions options, Send send, StateForwarder* forwarder,
                       trace::Tracer& tracer, const clock::Clock* clock)
    : options_(std::move(options)),
      send_(std::move(send)),
      forwarder_(forwarder),
      tracer_(tracer),
      clock_(clock) {
  if (clock_ == nullptr) {
    static const clock::SystemClock system;
    clock_ = &system;
  }
}

void SimSession::fail(std::string why) {
  fatal_ = std::move(why);
  phase_ = Phase::kFailed;
}

void SimSession::on_connected() {
  if (ended())
    return;
  parser_ = sim::FrameParser(sim::Sender::kServer);
  phase_ = Phase::kGreeting;
  send_(sim::encode(sim::Hello{options_.client_name}));
}

void SimSession::on_disconnected() {
  if (ended())
    return;
  phase_ = Phase::kDisconnected;
  for (auto& [i, d] : driven_) {
    d.attached = false;
    d.answered = false;
  }
}

bool SimSession::on_bytes(std::span<const std::uint8_t> bytes) {
  while (!bytes.empty()) {
    const auto status = parser_.parse(bytes);
    if (!status) {
      last_error_ = fmt::format("malformed data from the server: {}", to_string(status.error()));
      return false;
    }
    if (*status == sim::FrameParser::Status::kNeedMore)
      break;
    const auto msg = sim::decode_server(parser_.frame());
    if (!msg) {
      last_error_ = fmt::format("malformed {} message from the server: {}",
                                to_string(parser_.frame().type), to_string(msg.error()));
      return false;
    }
    if (!handle(*msg))
      return false;
  }
  return true;
}

bool SimSession::handle(const sim::ServerMessage& m) {
  if (const auto* w = std::get_if<sim::Welcome>(&m))
    return on_welcome(*w);
  if (phase_ != Phase::kRunning) {
    last_error_ = "the server sent a message before Welcome";
    return false;
  }
  if (const auto* r = std::get_if<sim::AttachResult>(&m)) {
    on_attach_result(*r);
    return phase_ != Phase::kFailed;
  }
  if (const auto* f = std::get_if<sim::StateFrame>(&m)) {
    on_state(*f);
    return true;
  }
  if (const auto* s = std::get_if<sim::SignalStates>(&m)) {
    // On to the RSUs first: the light change is on its way to the SPATEM before anything else.
    if (signal_forwarder_ != nullptr)
      signal_forwarder_->forward(*s);
    // Every junction's groups come in each message; a junction missing from it has none left.
    std::map<std::uint16_t, JunctionSignals> now;
    for (const sim::SignalGroupState& g : s->groups) {
      JunctionSignals& j = now[g.intersection_id];
      j.world_time_ms = s->world_time_ms;
      j.groups.push_back(g);
    }
    signals_ = std::move(now);
    lights_.update(*s);
    ++signal_updates_;
    return true;
  }
  if (const auto* d = std::get_if<sim::DriverChanged>(&m)) {
    if (d->vehicle < welcome_->vehicles.size())
      welcome_->vehicles[d->vehicle].driver = d->driver;
    // A vehicle we drove before a reconnection, still held by our old connection then: take
    // it back as soon as the server lets it go.
    const auto it = driven_.find(d->vehicle);
    if (d->driver.empty() && it != driven_.end() && it->second.answered && !it->second.attached) {
      it->second.answered = false;
      send_(sim::encode(sim::Attach{sim::Role::kDriver, d->vehicle}));
    }
    return true;
  }
  const auto& c = std::get<sim::Closing>(m);
  last_error_ =
      fmt::format("the server closed the connection ({}): {}", to_string(c.reason), c.text);
  // The vehicles stay as they were: the view keeps showing the last picture of the own car.
  if (c.reason == sim::CloseReason::kScenarioFinished && !options_.reconnect)
    phase_ = Phase::kFinished;
  return false;
}

bool SimSession::on_welcome(const sim::Welcome& w) {
  if (phase_ != Phase::kGreeting) {
    last_error_ = "the server sent a second Welcome";
    return false;
  }
  if (options_.list_only) {
    welcome_ = w;
    phase_ = Phase::kListed;
    return false;
  }
  // The emulator dates every fix on the world's clock that the server fixed (docs/time.md).
  if (forwarder_)
    forwarder_->set_world_start(w.world_start_ns);
  const bool same_world =
      welcome_ && welcome_->scenario_json == w.scenario_json && welcome_->map_text == w.map_text;
  if (!same_world) {
    try {
      // The map comes with the scenario: an OpenDRIVE map's text in Welcome, so that this
      // computer needs no copy of the file.
      scenario_ = scenario::parse(
          w.scenario_json, "scenario sent by the server",
          w.map_text.empty() ? std::nullopt : std::optional<std::string_view>(w.map_text));
      map_ = std::make_shared<const map::ScenarioMap>(*scenario_);
      drive_map_ = std::make_unique<DriveMap>(map_);
      sizes_.clear();
      for (const scenario::Vehicle& v : scenario_->vehicles)
        sizes_.push_back({v.station_id, v.model.length_m, v.model.width_m});
    } catch (const std::exception& e) {
      fail(fmt::format("cannot use the server's scenario: {}", e.what()));
      return false;
    }
  }
  welcome_ = w;
  signals_.clear();  // the server sends the lights right after Welcome
  ++signal_updates_;
  lights_ = TrafficLights(w.world_start_ns);

  // Which vehicles to drive: by id, plus every scripted one with --scripted.
  std::vector<std::uint16_t> wanted;
  for (const auto& id : options_.vehicles) {
    const auto it = std::find_if(w.vehicles.begin(), w.vehicles.end(),
                                 [&](const sim::VehicleInfo& v) { return v.id == id; });
    if (it == w.vehicles.end()) {
      std::string known;
      for (const auto& v : w.vehicles)
        known += (known.empty() ? "" : ", ") + v.id;
      fail(fmt::format("--vehicle {}: the server's scenario has no such vehicle (it has {})", id,
                       known.empty() ? "none" : known));
      return false;
    }
    wanted.push_back(it->index);
  }
  if (options_.scripted) {
    for (const auto& v : w.vehicles) {
      if (v.driver_kind != sim::DriverKind::kHuman)
        wanted.push_back(v.index);
    }
  }
  std::sort(wanted.begin(), wanted.end());
  wanted.erase(std::unique(wanted.begin(), wanted.end()), wanted.end());

  if (!same_world)
    driven_.clear();
  for (const std::uint16_t i : wanted) {
    Driven& d = driven_[i];
    d.index = i;
    d.station_id = w.vehicles[i].station_id;
    if (!d.script && w.vehicles[i].driver_kind != sim::DriverKind::kHuman) {
      const scenario::Vehicle* v = scenario_->find_vehicle(w.vehicles[i].id);
      if (v == nullptr) {
        fail(fmt::format("vehicle {} is in the server's list but not in its scenario",
                         w.vehicles[i].id));
        return false;
      }
      d.lights = v->lights;
      try {
        d.script = make_scripted_driver(*v, *scenario_, *drive_map_);
      } catch (const std::exception& e) {
        fail(fmt::format("vehicle {}: cannot build its scripted driver: {}", v->id, e.what()));
        return false;
      }
    }
  }
  phase_ = Phase::kRunning;
  if (driven_.empty()) {
    send_(sim::encode(sim::Attach{sim::Role::kWatcher, 0}));
  }
  for (auto& [i, d] : driven_)
    send_(sim::encode(sim::Attach{sim::Role::kDriver, i}));
  return true;
}

void SimSession::on_attach_result(const sim::AttachResult& r) {
  if (r.role != sim::Role::kDriver)
    return;
  const auto it = driven_.find(r.vehicle);
  if (it == driven_.end())
    return;
  Driven& d = it->second;
  d.answered = true;
  const std::string& id = welcome_->vehicles[r.vehicle].id;
  if (r.status == sim::AttachStatus::kOk) {
    d.attached = true;
    d.ever_attached = true;
    spdlog::info("driving vehicle {} (station {}) with {}", id, d.station_id,
                 d.script ? "its scenario's script" : "the human input");
    return;
  }
  if (d.ever_attached && r.status == sim::AttachStatus::kAlreadyDriven) {
    // After a reconnection the server may not yet have noticed that our old connection is
    // gone; DriverChanged will say when the vehicle is free.
    spdlog::warn("vehicle {} is still held ({}); attaching again when it is free", id, r.reason);
    return;
  }
  spdlog::error("cannot drive vehicle {}: {}{}{}", id, to_string(r.status),
                r.reason.empty() ? "" : ": ", r.reason);
  if (std::all_of(driven_.begin(), driven_.end(), [](const auto& e) {
        return e.second.answered && !e.second.attached && !e.second.ever_attached;
      })) {
    fail("none of the requested vehicles could be attached");
  }
}

void SimSession::on_state(const sim::StateFrame& f) {
  ++frames_;
  latest_ = f;
  if (forwarder_ != nullptr) {
    // The tick's states leave together, before the controls, in as few datagrams as fit.
    tick_states_.clear();
    for (const auto& [i, d] : driven_)
      if (d.attached && i < f.vehicles.size())
        tick_states_.push_back(f.vehicles[i]);
    if (options_.forward_undriven) {
      for (std::size_t i = 0; i < welcome_->vehicles.size() && i < f.vehicles.size(); ++i) {
        const auto it = driven_.find(static_cast<std::uint16_t>(i));
        if (welcome_->vehicles[i].driver.empty() && (it == driven_.end() || !it->second.attached))
          tick_states_.push_back(f.vehicles[i]);
      }
    }
    if (!tick_states_.empty())
      forwarder_->forward_tick(tick_states_);
  }
  // Where every vehicle is, located once for all scripted drivers of this frame.
  std::optional<Traffic> traffic;
  // The controls of every vehicle this client drives leave in one message, as the states came.
  batch_.entries.clear();
  const bool tracing = tracer_.enabled();
  for (auto& [i, d] : driven_) {
    if (!d.attached || i >= f.vehicles.size())
      continue;
    const wire::VehicleState& s = f.vehicles[i];
    if (d.script && !traffic) {
      traffic = drive_map_->observe(f.vehicles, sizes_);
      traffic->lights = &lights_;
    }
    sim::ControlsMsg c;
    c.vehicle = i;
    if (d.script) {
      // A scripted driver reads its input (the state) now.
      c.input_ns = clock::to_unix_ns(clock_->wall_now());
      c.controls = d.script->update(s, *traffic);
      c.lights = d.lights;
    } else {
      c.controls = human_.controls;
      c.lights = human_.lights;
      c.input_ns = human_sampled_ns_;
    }
    ++d.seq;
    // Start of t1 (docs/tracing.md): the server traces the same input_ns when a step applies it.
    if (tracing) {
      tracer_.record("client.input", {{"station", d.station_id},
                                      {"seq", static_cast<unsigned long long>(d.seq)},
                                      {"input_ns", c.input_ns}});
    }
    batch_.entries.push_back(c);
  }
  if (batch_.entries.size() == 1)
    send_(sim::encode(batch_.entries.front()));
  else if (!batch_.entries.empty())
    send_(sim::encode(batch_));
  // After the forwarded states and the controls: a view never delays t1 or t2.
  if (frame_observer_)
    frame_observer_(f);
}

std::vector<std::uint16_t> SimSession::driven() const {
  std::vector<std::uint16_t> out;
  for (const auto& [i, d] : driven_) {
    if (d.attached)
      out.push_back(i);
  }
  return out;
}

bool SimSession::human_driven(std::uint16_t index) const {
  const auto it = driven_.find(index);
  return it != driven_.end() && it->second.attached && !it->second.script;
}

}  // namespace tb::client
