#include "sim-client/net/forwarder.hpp"

#include <algorithm>
#include <charconv>
#include <stdexcept>

#include <spdlog/spdlog.h>
#include <boost/asio/ip/udp.hpp>

#include "common/wire/signal_feed.hpp"

namespace tb::client {

std::pair<std::string, std::uint16_t> split_host_port(const std::string& text,
                                                      std::uint16_t default_port) {
  std::string host = text;
  std::string port;
  if (!text.empty() && text.front() == '[') {
    const auto close = text.find(']');
    if (close == std::string::npos)
      throw std::invalid_argument("\"" + text + "\": missing ']' after the IPv6 address");
    host = text.substr(1, close - 1);
    if (close + 1 < text.size()) {
      if (text[close + 1] != ':')
        throw std::invalid_argument("\"" + text + "\": expected ':' after ']'");
      port = text.substr(close + 2);
    }
  } else if (const auto colon = text.rfind(':'); colon != std::string::npos) {
    host = text.substr(0, colon);
    port = text.substr(colon + 1);
  }
  if (host.empty())
    throw std::invalid_argument("\"" + text + "\": no host");
  if (port.empty() && text.find(':') == std::string::npos)
    return {host, default_port};
  unsigned value = 0;
  const auto [end, ec] = std::from_chars(port.data(), port.data() + port.size(), value);
  if (ec != std::errc{} || end != port.data() + port.size() || value == 0 || value > 65535)
    throw std::invalid_argument("\"" + text + "\": port \"" + port + "\" is not in 1..65535");
  return {host, static_cast<std::uint16_t>(value)};
}

UdpSink::UdpSink(boost::asio::io_context& io, const std::string& host_port) : socket_(io) {
  const auto [host, port] = split_host_port(host_port, 4700);
  boost::asio::ip::udp::resolver resolver(io);
  boost::system::error_code ec;
  const auto results = resolver.resolve(host, std::to_string(port), ec);
  if (ec || results.empty())
    throw std::runtime_error("cannot resolve emulator address \"" + host_port +
                             "\": " + ec.message());
  destination_ = *results.begin();
  socket_.open(destination_.protocol());
}

bool UdpSink::send(std::span<const std::uint8_t> datagram) {
  boost::system::error_code ec;
  socket_.send_to(boost::asio::buffer(datagram.data(), datagram.size()), destination_, 0, ec);
  return !ec;
}

void StateForwarder::forward_tick(std::span<const wire::VehicleState> states,
                                  std::size_t max_datagram) {
  const std::size_t per = wire::states_per_batch(max_datagram);
  for (std::size_t first = 0; first < states.size(); first += per) {
    const auto part = states.subspan(first, std::min(per, states.size() - first));
    const std::int64_t now = clock::to_unix_ns(clock_.wall_now());
    chunk_.assign(part.begin(), part.end());
    for (auto& s : chunk_)
      s.send_wall_ns = now;
    buffer_.resize(wire::batch_datagram_size(chunk_.size()));
    buffer_.resize(wire::encode_batch(chunk_, buffer_, world_start_ns_));
    if (!sink_.send(buffer_)) {
      // Logged at the first failure and then every 1000th, so a missing emulator does not flood.
      if (failed_datagrams_++ % 1000 == 0)
        spdlog::warn("cannot send vehicle states to the emulator ({} states failed so far)",
                     failed_ + chunk_.size());
      failed_ += chunk_.size();
      continue;
    }
    ++datagrams_;
    sent_ += chunk_.size();
    for (const auto& state : chunk_) {
      // x, y, v, yaw let the report tell the steps that changed the state (a moving car) from
      // those that did not (a standing one), docs/tracing.md; sim_ns the warm-up (negative)
      // from the physics.
      tracer_.record_at(state.send_wall_ns, "client.forward",
                        {{"station", state.station_id},
                         {"tick", static_cast<unsigned long long>(state.tick)},
                         {"sim_ns", static_cast<long long>(state.sim_time_ns)},
                         {"step_ns", static_cast<long long>(state.step_wall_ns)},
                         {"x", state.position[0]},
                         {"y", state.position[1]},
                         {"v", static_cast<double>(state.speed)},
                         {"yaw", static_cast<double>(state.yaw)}});
    }
  }
}

std::string signal_feed_address(const std::string& emulator) {
  const auto [host, port] = split_host_port(emulator, 4700);
  if (port > 65535 - wire::kSignalFeedPortOffset)
    throw std::invalid_argument("\"" + emulator + "\": the signal feed goes to the port + " +
                                std::to_string(wire::kSignalFeedPortOffset) + ", beyond 65535");
  const std::string next = std::to_string(port + wire::kSignalFeedPortOffset);
  return host.find(':') != std::string::npos ? "[" + host + "]:" + next : host + ":" + next;
}

void SignalForwarder::forward(const wire::sim::SignalStates& states) {
  const auto datagram = wire::encode_signal_feed(states);
  if (!datagram) {
    if (too_large_++ == 0)
      spdlog::warn("signal states of {} groups do not fit a datagram: not sent to the emulator",
                   states.groups.size());
    return;
  }
  if (!sink_.send(*datagram)) {
    if (failed_++ % 1000 == 0)
      spdlog::warn("cannot send signal states to the emulator ({} failed so far)", failed_);
    return;
  }
  ++sent_;
  // The first hop of a light change on its way to the SPATEM (issue 34's latency figure).
  tracer_.record("client.signals",
                 {{"world_ms", static_cast<long long>(states.world_time_ms)},
                  {"groups", static_cast<unsigned long long>(states.groups.size())}});
}

}  // namespace tb::client
