#pragma once
/// @file Relay (issue 35, `--relay HOST:PORT`): every datagram that reaches this emulator's
/// vehicle-state socket goes on, unchanged, to each relay target's HOST:PORT, and every one on
/// its signal-feed socket to HOST:PORT+1 — so that, in a swarm, the manager's emulator hands
/// the whole stream to every other node's emulator and the sim-clients keep one address.
///
/// Pure logic: a target's sinks are attached once its name resolves (RelayResolver in main.cpp
/// does that, and again when the name moves); an absent target (ICMP unreachable) is paused
/// and said once, by PeerHealth, and said again when it takes datagrams again.

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "common/clock/clock.hpp"
#include "network-emulator/app/datagram_sink.hpp"
#include "network-emulator/app/peer_health.hpp"

namespace tb::emu {

struct RelayTarget {
  std::string host;  ///< a name (resolved, retried) or an IPv4 address
  std::uint16_t port = 0;
  std::string text() const { return host + ":" + std::to_string(port); }
};

/// "HOST:PORT" with a port that leaves room for the signal feed's PORT+1; empty otherwise.
std::optional<RelayTarget> parse_relay_target(const std::string& text);

class Relay {
 public:
  Relay(const clock::Clock& clock, std::vector<RelayTarget> targets);

  const std::vector<RelayTarget>& targets() const { return targets_; }
  /// Target @p k's name resolved: from now on its datagrams go to @p states (HOST:PORT) and
  /// @p signals (HOST:PORT+1), which must outlive the relay or the next attach/detach.
  void attach(std::size_t k, DatagramSink& states, DatagramSink& signals);
  void detach(std::size_t k);

  void relay_states(std::span<const std::uint8_t> datagram);
  void relay_signals(std::span<const std::uint8_t> datagram);

  /// Told when a target stops taking datagrams (with the reason) and when it takes them again.
  using Event = std::function<void(const RelayTarget&, bool up, const std::string& why)>;
  void set_events(Event e) { events_ = std::move(e); }

  std::uint64_t relayed() const { return relayed_; }
  /// Datagrams not relayed: target not resolved yet, or paused as absent.
  std::uint64_t not_relayed() const { return not_relayed_; }

 private:
  struct Target {
    DatagramSink* states = nullptr;
    DatagramSink* signals = nullptr;
    std::unique_ptr<PeerHealth> health;
  };
  void relay(std::span<const std::uint8_t> d, bool signals);

  const clock::Clock& clock_;
  std::vector<RelayTarget> targets_;
  std::vector<Target> state_;
  Event events_;
  std::uint64_t relayed_ = 0;
  std::uint64_t not_relayed_ = 0;
};

}  // namespace tb::emu
