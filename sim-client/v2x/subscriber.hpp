#pragma once
/// @file sim-client's read-only MQTT connection: the broker's `hmi` reader account subscribes
/// to the topics V2xMonitor reads (`--mqtt HOST[:PORT]`). The connection is common/mqtt's
/// client (its own network thread, reconnection with backoff); the monitor is fed from there.

#include <cstdint>
#include <memory>
#include <string>

#include "common/clock/clock.hpp"
#include "common/mqtt/mosquitto_client.hpp"
#include "sim-client/v2x/monitor.hpp"

namespace tb::client::v2x {

struct SubscriberOptions {
  std::string host = "127.0.0.1";
  std::uint16_t port = 1883;
  /// The read-only account of docker/mosquitto/gen-broker-config (default reader hmi:hmi).
  std::string username = "hmi";
  std::string password = "hmi";
};

class V2xSubscriber {
 public:
  /// @throws tb::mqtt::MqttError when libmosquitto cannot make a client.
  V2xSubscriber(const clock::Clock& clock, V2xMonitor& monitor, SubscriberOptions options);
  ~V2xSubscriber();
  V2xSubscriber(const V2xSubscriber&) = delete;
  V2xSubscriber& operator=(const V2xSubscriber&) = delete;

  /// Connects in the background (a broker that is down is retried).
  void start();
  void stop();
  bool connected() const;
  /// For the HUD: "MQTT HOST:PORT", "MQTT HOST:PORT: connecting", "... refused: REASON".
  std::string status() const;

 private:
  const clock::Clock& clock_;
  V2xMonitor& monitor_;
  SubscriberOptions options_;
  std::unique_ptr<mqtt::MosquittoClient> client_;
};

}  // namespace tb::client::v2x
