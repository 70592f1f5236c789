#include "its-station/apps/mqtt/publisher.hpp"

namespace tb::its::apps::mqtt {
namespace {
// Envelope origins: what this station produced itself, and what it heard over the air.
constexpr std::string_view kOriginSelf = "self";
constexpr std::string_view kOriginRemote = "remote";
constexpr std::string_view kOriginApplication = "on_board_application";
// Sources silent this long are forgotten, so that the rate limiter's table stays small.
constexpr auto kForgetSourceAfter = std::chrono::seconds{10};
}  // namespace

StationPublisher::StationPublisher(const clock::Clock& clock, tb::mqtt::MqttSink& sink,
                                   PublisherConfig cfg)
    : clock_(clock), sink_(sink), cfg_(std::move(cfg)), topics_(cfg_.prefix, cfg_.station_id) {}

void StationPublisher::send(const std::string& topic, std::string_view type,
                            std::string_view origin, nlohmann::json message, tb::mqtt::Qos qos,
                            bool retain) {
  sink_.publish(
      topic, envelope(type, origin, cfg_.station_id, clock_.wall_now(), std::move(message)).dump(),
      qos, retain);
}

void StationPublisher::publish_state(const StationState& s) {
  sink_.publish(topics_.state(), state_payload(cfg_.station_id, clock_.wall_now(), s),
                tb::mqtt::Qos::kAtMostOnce, true);
}

bool StationPublisher::publish_cam(const ReceivedCam& c) {
  const clock::SteadyTime now = clock_.steady_now();
  const auto it = last_cam_.find(c.station_id);
  if (it != last_cam_.end() && now - it->second < cfg_.cam_min_interval) {
    ++cams_suppressed_;
    return false;
  }
  last_cam_[c.station_id] = now;
  if (last_cam_.size() > 256) {
    std::erase_if(last_cam_, [&](const auto& kv) { return now - kv.second > kForgetSourceAfter; });
  }
  const std::string topic = topics_.cam_in(c.station_id);
  sink_.publish(topic, received_cam_payload(cfg_.station_id, clock_.wall_now(), c),
                tb::mqtt::Qos::kAtMostOnce, false);
  if (tracer_ != nullptr) {
    tracer_->record("its.mqtt", {{"station", cfg_.station_id},
                                 {"topic", std::string_view{topic}},
                                 {"from", c.station_id},
                                 {"gdt", unsigned{c.generation_delta_time}}});
  }
  return true;
}

void StationPublisher::publish_denm_received(const DenmView& d) {
  send(topics_.denm_in(d.action_id.originating_station_id), "denm", kOriginRemote, denm_message(d),
       tb::mqtt::Qos::kAtLeastOnce, false);
}

void StationPublisher::publish_denm_sent(const DenmView& d) {
  send(topics_.denm_out(), "denm", kOriginSelf, denm_message(d), tb::mqtt::Qos::kAtLeastOnce,
       false);
}

void StationPublisher::publish_warning(const LcrwWarning& w) {
  const std::string topic = topics_.lcrw();
  send(topic, "lcrw_warning", kOriginApplication, lcrw_message(w), tb::mqtt::Qos::kAtLeastOnce,
       false);
  if (tracer_ != nullptr) {
    tracer_->record("its.mqtt", {{"station", cfg_.station_id},
                                 {"topic", std::string_view{topic}},
                                 {"from", w.other_station_id},
                                 {"gdt", unsigned{generation_delta_time(w.other_state_time)}},
                                 // With from and gdt, names the one message an HMI's receipt
                                 // (hmi.lcrw, docs/tracing.md) is about: every evaluation
                                 // while a warning is active publishes again.
                                 {"own_ms", unix_ms(w.own_state_time)},
                                 {"event", to_string(w.event)}});
  }
}

void StationPublisher::publish_signal(const signal::SignalStatus& s) {
  const std::string topic = topics_.signal();
  send(topic, "signal", kOriginApplication, signal_message(s), tb::mqtt::Qos::kAtMostOnce, false);
  if (tracer_ != nullptr) {
    // intersection, lane and state name the status an HMI shows; own_ms its evaluation.
    tracer_->record("its.mqtt", {{"station", cfg_.station_id},
                                 {"topic", std::string_view{topic}},
                                 {"intersection", unsigned{s.intersection_id}},
                                 {"lane", s.on_lane ? int{s.lane_id} : -1},
                                 {"state", static_cast<int>(s.state)},
                                 {"own_ms", unix_ms(s.time)}});
  }
}

void StationPublisher::publish_rlvw(const signal::RlvwWarning& w) {
  const std::string topic = topics_.rlvw();
  send(topic, "rlvw_warning", kOriginApplication, rlvw_message(w), tb::mqtt::Qos::kAtLeastOnce,
       false);
  if (tracer_ != nullptr) {
    tracer_->record("its.mqtt", {{"station", cfg_.station_id},
                                 {"topic", std::string_view{topic}},
                                 {"intersection", unsigned{w.intersection_id}},
                                 {"lane", int{w.lane_id}},
                                 {"own_ms", unix_ms(w.updated_at)},
                                 {"event", to_string(w.event)}});
  }
}

}  // namespace tb::its::apps::mqtt
