#pragma once
/// @file Forwarding vehicle states to the network emulator: the states of one physics tick in
/// as few batch datagrams as fit (docs/wire.md; DESIGN.md), each state stamped with the send
/// time of its datagram. The thesis (3.1.4) sent one datagram per vehicle per tick; batching
/// keeps every state's own tick and times, and no state waits for another tick.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>

#include "common/clock/clock.hpp"
#include "common/trace/tracer.hpp"
#include "common/wire/sim_protocol.hpp"
#include "common/wire/vehicle_state.hpp"

namespace tb::client {

/// Where forwarded datagrams go; a narrow interface so that tests can capture them.
class DatagramSink {
 public:
  virtual ~DatagramSink() = default;
  /// Returns false if the datagram could not be sent (it is dropped, never retried).
  virtual bool send(std::span<const std::uint8_t> datagram) = 0;
};

/// A connected UDP socket. Send errors (no emulator listening yet: ECONNREFUSED) are counted,
/// not thrown: the emulator may start after the client.
class UdpSink final : public DatagramSink {
 public:
  /// @throws std::runtime_error naming @p host_port if it cannot be resolved.
  UdpSink(boost::asio::io_context& io, const std::string& host_port);
  bool send(std::span<const std::uint8_t> datagram) override;
  const boost::asio::ip::udp::endpoint& destination() const { return destination_; }

 private:
  boost::asio::ip::udp::socket socket_;
  boost::asio::ip::udp::endpoint destination_;
};

/// Splits "HOST:PORT" ("[v6]:PORT" for IPv6). @throws std::invalid_argument naming the text.
std::pair<std::string, std::uint16_t> split_host_port(const std::string& text,
                                                      std::uint16_t default_port);

class StateForwarder {
 public:
  StateForwarder(const clock::Clock& clock, DatagramSink& sink,
                 trace::Tracer& tracer = trace::global())
      : clock_(clock), sink_(sink), tracer_(tracer) {}

  /// Sends the states of one tick in datagrams of up to @p max_datagram bytes (at least one
  /// state each), stamping each datagram's states with its send time; records `client.forward`
  /// per state sent.
  void forward_tick(std::span<const wire::VehicleState> states,
                    std::size_t max_datagram = wire::kDefaultBatchDatagramSize);
  /// UTC of sim time 0 (Unix ns) from the server's Welcome, sent in every batch so that the
  /// emulator dates fixes on the world's clock; wire::kUnknownWorldStart until then.
  void set_world_start(std::int64_t unix_ns) { world_start_ns_ = unix_ns; }
  /// A tick of one state.
  void forward(const wire::VehicleState& state) { forward_tick({&state, 1}); }
  std::uint64_t sent() const { return sent_; }      ///< states
  std::uint64_t failed() const { return failed_; }  ///< states in datagrams that failed
  std::uint64_t datagrams() const { return datagrams_; }

 private:
  const clock::Clock& clock_;
  DatagramSink& sink_;
  trace::Tracer& tracer_;
  std::uint64_t sent_ = 0;
  std::uint64_t failed_ = 0;
  std::uint64_t datagrams_ = 0;
  std::uint64_t failed_datagrams_ = 0;
  std::int64_t world_start_ns_ = wire::kUnknownWorldStart;
  std::vector<wire::VehicleState> chunk_;
  std::vector<std::uint8_t> buffer_;
};

/// Where the signal feed goes for an emulator whose state address is @p emulator ("HOST:PORT",
/// default port 4700): the same host, the port + wire::kSignalFeedPortOffset (4700 → 4701).
/// @throws std::invalid_argument naming the text (also for port 65535, which has no next).
std::string signal_feed_address(const std::string& emulator);

/// Passes every SignalStates the server sends on to the network emulator (issue 34), one
/// sim-protocol frame per datagram (common/wire/signal_feed.hpp), at once: the emulator feeds
/// each RSU its junction's groups. Every client that forwards vehicle states does this; the
/// emulator keeps one copy per world_time_ms.
class SignalForwarder {
 public:
  explicit SignalForwarder(DatagramSink& sink, trace::Tracer& tracer = trace::global())
      : sink_(sink), tracer_(tracer) {}
  void forward(const wire::sim::SignalStates& states);
  std::uint64_t sent() const { return sent_; }      ///< datagrams
  std::uint64_t failed() const { return failed_; }  ///< datagrams the socket refused
  /// Messages with more groups than a datagram holds (wire::kMaxSignalFeedDatagram): dropped.
  std::uint64_t too_large() const { return too_large_; }

 private:
  DatagramSink& sink_;
  trace::Tracer& tracer_;
  std::uint64_t sent_ = 0, failed_ = 0, too_large_ = 0;
};

}  // namespace tb::client
