#pragma once
/// @file The narrow interface between publishers (the station's, tests') and an MQTT connection.

#include <string>
#include <string_view>

namespace tb::mqtt {

enum class Qos : int { kAtMostOnce = 0, kAtLeastOnce = 1 };

class MqttSink {
 public:
  virtual ~MqttSink() = default;
  /// Hands one message to the connection. QoS 0 messages may be lost while it is down; QoS 1
  /// messages are kept (bounded) until the broker acknowledges them.
  virtual void publish(std::string_view topic, std::string payload, Qos qos, bool retain) = 0;
};

}  // namespace tb::mqtt
