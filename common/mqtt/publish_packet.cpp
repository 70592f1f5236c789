#include "common/mqtt/publish_packet.hpp"

#include <mosquitto.h>

#include <cstdint>

namespace tb::mqtt {
namespace {

constexpr std::uint8_t kPublish = 0x30;  // packet type 3 in the high nibble (clause 2.2.1)
constexpr std::uint8_t kRetain = 0x01;   // clause 3.3.1.3
constexpr std::size_t kMaxTopic = 65535;

std::string printable(std::string_view topic) {
  std::string s;
  for (const char c : topic.substr(0, 80)) {
    s += (c >= 0x20 && c < 0x7f) ? c : '?';
  }
  return topic.size() > 80 ? s + "…" : s;
}

}  // namespace

void append_qos0_publish(std::string& out, std::string_view topic, std::string_view payload,
                         bool retain) {
  if (topic.empty() || topic.size() > kMaxTopic) {
    throw PacketError("mqtt: topic '" + printable(topic) + "' has " + std::to_string(topic.size()) +
                      " bytes; a topic name has 1 to 65535");
  }
  // libmosquitto's own checks, the ones mosquitto_publish makes (clauses 1.5.3 and 4.7.1).
  const int len = static_cast<int>(topic.size());
  if (topic.find('\0') != std::string_view::npos ||
      mosquitto_validate_utf8(topic.data(), len) != MOSQ_ERR_SUCCESS) {
    throw PacketError("mqtt: topic '" + printable(topic) + "' is not valid UTF-8 without NUL");
  }
  if (mosquitto_pub_topic_check2(topic.data(), static_cast<std::size_t>(len)) != MOSQ_ERR_SUCCESS) {
    throw PacketError("mqtt: topic '" + printable(topic) +
                      "' has a wildcard; one cannot publish to a filter");
  }
  const std::size_t remaining = 2 + topic.size() + payload.size();
  if (remaining > kMaxRemainingLength) {
    throw PacketError("mqtt: a message of " + std::to_string(payload.size()) + " bytes to '" +
                      printable(topic) + "' is larger than a packet can be");
  }
  out.push_back(static_cast<char>(kPublish | (retain ? kRetain : 0)));
  // Remaining Length: 7 bits a byte, least significant first, the top bit saying more follows.
  std::size_t x = remaining;
  do {
    std::uint8_t b = x % 128;
    x /= 128;
    if (x > 0) {
      b |= 0x80;
    }
    out.push_back(static_cast<char>(b));
  } while (x > 0);
  out.push_back(static_cast<char>(topic.size() >> 8));
  out.push_back(static_cast<char>(topic.size() & 0xff));
  out.append(topic);
  out.append(payload);
}

}  // namespace tb::mqtt
