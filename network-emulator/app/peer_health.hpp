#pragma once
/// @file PeerHealth: notices a receiver that went away and keeps the sender from flooding it.
///
/// A connected UDP socket learns of an absent receiver from ICMP port/host unreachable and
/// reports it as an error on a later send. One such error pauses the sender (logged once);
/// while paused it tries again once per retry interval, and it counts as back only after two
/// sends in a row succeed (a single probe always "succeeds", since the ICMP answer to it
/// arrives later). A full socket buffer (would_block) drops one datagram and pauses nothing.

#include <cstdint>
#include <system_error>

#include "common/clock/clock.hpp"

namespace tb::emu {

class PeerHealth {
 public:
  enum class Change { kNone, kPaused, kResumed };

  explicit PeerHealth(const clock::Clock& clock, clock::Duration retry = std::chrono::seconds(1))
      : clock_(clock), retry_(retry) {}

  /// Whether to send now. False while paused, except for one probe per retry interval.
  bool should_send();
  /// Records the outcome of a send that should_send() allowed.
  Change record(std::error_code ec);

  bool paused() const { return state_ != State::kHealthy; }
  std::error_code last_error() const { return last_error_; }
  std::uint64_t skipped() const { return skipped_; }

  /// Errors that are about this moment's socket buffer, not about the receiver.
  static bool is_transient(std::error_code ec);

 private:
  enum class State { kHealthy, kPaused, kProbing };
  const clock::Clock& clock_;
  clock::Duration retry_;
  State state_ = State::kHealthy;
  clock::SteadyTime retry_at_{};
  int probe_successes_ = 0;
  std::error_code last_error_;
  std::uint64_t skipped_ = 0;
};

}  // namespace tb::emu
