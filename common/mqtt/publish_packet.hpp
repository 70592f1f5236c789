#pragma once
/// @file QoS 0 PUBLISH packets of MQTT 3.1.1, encoded here so that a batch of them leaves in one
/// send() (issue 33): libmosquitto writes each packet with its own write() and a byte to an
/// internal socket pair per publish, which was the largest share of a full station's system
/// calls (docs/latency.md). libmosquitto keeps the connection, QoS 1 and the subscriptions.

#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>

namespace tb::mqtt {

class PacketError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// The largest Remaining Length the four-byte encoding holds (MQTT 3.1.1 clause 2.2.3).
inline constexpr std::size_t kMaxRemainingLength = 268'435'455;

/// Appends one PUBLISH packet with QoS 0 (clause 3.3: no packet identifier, DUP 0) to @p out.
/// @throws PacketError naming the topic when it is not a valid topic name to publish to
/// (empty, longer than 65535 bytes, wildcards, NUL, not UTF-8: clauses 1.5.3, 4.7) or when the
/// packet would exceed kMaxRemainingLength; @p out is then unchanged.
void append_qos0_publish(std::string& out, std::string_view topic, std::string_view payload,
                         bool retain);

}  // namespace tb::mqtt
