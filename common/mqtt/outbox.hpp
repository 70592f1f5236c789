#pragma once
/// @file The bounded queue of QoS 1 messages that wait for a broker connection.

#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>

#include "common/mqtt/sink.hpp"

namespace tb::mqtt {

struct OutMessage {
  std::string topic;
  std::string payload;
  Qos qos = Qos::kAtLeastOnce;
  bool retain = false;
};

/// First in, first out; when full, the oldest message gives way to the newest (a warning about
/// the present matters more than one about the past) and is counted as dropped.
class Outbox {
 public:
  explicit Outbox(std::size_t capacity) : capacity_(capacity == 0 ? 1 : capacity) {}
  /// Returns true if an older message was dropped to make room.
  bool push(OutMessage m);
  std::optional<OutMessage> pop();
  /// Puts a message back at the head (a hand-over that failed).
  void push_front(OutMessage m) { q_.push_front(std::move(m)); }
  std::size_t size() const { return q_.size(); }
  bool empty() const { return q_.empty(); }
  std::size_t capacity() const { return capacity_; }
  std::uint64_t dropped() const { return dropped_; }

 private:
  std::size_t capacity_;
  std::deque<OutMessage> q_;
  std::uint64_t dropped_ = 0;
};

}  // namespace tb::mqtt
