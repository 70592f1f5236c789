#pragma once
/// @file Publishes a station's state, received CAMs and DENMs, and LCRW warnings to MQTT.

#include <chrono>
#include <cstdint>
#include <map>

#include "common/clock/clock.hpp"
#include "common/mqtt/sink.hpp"
#include "common/trace/tracer.hpp"
#include "its-station/apps/lcrw/lcrw.hpp"
#include "its-station/apps/mqtt/messages.hpp"

namespace tb::its::apps::mqtt {

struct PublisherConfig {
  std::string prefix = "its";
  std::uint32_t station_id = 0;
  /// At most one received CAM per source station in this interval reaches MQTT: CAMs arrive at
  /// up to 10 Hz per neighbour (EN 302 637-2), more than a dashboard or a logger needs.
  clock::Duration cam_min_interval = std::chrono::milliseconds{200};
};

class StationPublisher {
 public:
  StationPublisher(const clock::Clock& clock, tb::mqtt::MqttSink& sink, PublisherConfig cfg);

  /// QoS 0, retained: a subscriber that arrives sees the latest state at once.
  void publish_state(const StationState& s);
  /// QoS 0, rate-limited per source station; returns false when the CAM was held back.
  bool publish_cam(const ReceivedCam& c);
  /// QoS 1: DENMs are events, each of which matters.
  void publish_denm_received(const DenmView& d);
  void publish_denm_sent(const DenmView& d);
  /// QoS 1, not retained (a stale warning must not greet a late subscriber).
  void publish_warning(const LcrwWarning& w);
  /// The own lane's signal: QoS 0, not retained (a status a moment old is worthless; the
  /// application sends it at most once per fix).
  void publish_signal(const signal::SignalStatus& s);
  /// Red light violation warning events: QoS 1, not retained, like LCRW's.
  void publish_rlvw(const signal::RlvwWarning& w);

  /// `its.mqtt` records (docs/tracing.md: station, topic, from, gdt) for received CAMs and
  /// LCRW warnings, and for signal messages and RLVW events, go to @p tracer; null: none.
  void set_tracer(trace::Tracer* tracer) { tracer_ = tracer; }

  const Topics& topics() const { return topics_; }
  std::uint64_t cams_suppressed() const { return cams_suppressed_; }

 private:
  void send(const std::string& topic, std::string_view type, std::string_view origin,
            nlohmann::json message, tb::mqtt::Qos qos, bool retain);

  const clock::Clock& clock_;
  tb::mqtt::MqttSink& sink_;
  PublisherConfig cfg_;
  Topics topics_;
  std::map<std::uint32_t, clock::SteadyTime> last_cam_;
  std::uint64_t cams_suppressed_ = 0;
  trace::Tracer* tracer_ = nullptr;
};

}  // namespace tb::its::apps::mqtt
