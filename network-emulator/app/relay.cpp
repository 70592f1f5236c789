#include "network-emulator/app/relay.hpp"

#include <charconv>

namespace tb::emu {

std::optional<RelayTarget> parse_relay_target(const std::string& text) {
  const auto colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == text.size())
    return std::nullopt;
  const std::string host = text.substr(0, colon);
  if (host.find(':') != std::string::npos)
    return std::nullopt;  // IPv4 or a name: the emulator's sockets are IPv4
  unsigned port = 0;
  const char* b = text.data() + colon + 1;
  const char* e = text.data() + text.size();
  const auto [p, ec] = std::from_chars(b, e, port);
  if (ec != std::errc{} || p != e || port == 0 || port >= 65535)
    return std::nullopt;  // 65535 leaves no port for the signal feed
  return RelayTarget{host, static_cast<std::uint16_t>(port)};
}

Relay::Relay(const clock::Clock& clock, std::vector<RelayTarget> targets)
    : clock_(clock), targets_(std::move(targets)) {
  state_.resize(targets_.size());
  for (auto& t : state_)
    t.health = std::make_unique<PeerHealth>(clock_);
}

void Relay::attach(std::size_t k, DatagramSink& states, DatagramSink& signals) {
  Target& t = state_.at(k);
  t.states = &states;
  t.signals = &signals;
  // A new address is a new start: no pause carried over from the old one.
  t.health = std::make_unique<PeerHealth>(clock_);
}

void Relay::detach(std::size_t k) {
  state_.at(k).states = nullptr;
  state_.at(k).signals = nullptr;
}

void Relay::relay_states(std::span<const std::uint8_t> datagram) {
  relay(datagram, false);
}

void Relay::relay_signals(std::span<const std::uint8_t> datagram) {
  relay(datagram, true);
}

void Relay::relay(std::span<const std::uint8_t> d, bool signals) {
  for (std::size_t k = 0; k < state_.size(); ++k) {
    Target& t = state_[k];
    DatagramSink* sink = signals ? t.signals : t.states;
    if (!sink || !t.health->should_send()) {
      ++not_relayed_;
      continue;
    }
    const std::error_code ec = sink->send(d);
    switch (t.health->record(ec)) {
      case PeerHealth::Change::kPaused:
        if (events_)
          events_(targets_[k], false, ec.message());
        break;
      case PeerHealth::Change::kResumed:
        if (events_)
          events_(targets_[k], true, "takes datagrams again");
        break;
      case PeerHealth::Change::kNone:
        break;
    }
    if (ec)
      ++not_relayed_;
    else
      ++relayed_;
  }
}

}  // namespace tb::emu
