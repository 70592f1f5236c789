#pragma once
/// @file CanBus over UDP in cannelloni's format: the stand-in for a kernel without CAN.

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <boost/asio/steady_timer.hpp>

#include "common/can/can_bus.hpp"
#include "common/can/cannelloni.hpp"

namespace tb::can {

/// Counters of the receiving side.
struct UdpCanStats {
  std::uint64_t packets = 0;
  std::uint64_t frames = 0;
  std::uint64_t malformed = 0;      ///< packets that did not decode
  std::uint64_t sequence_gaps = 0;  ///< packets missing according to the sequence numbers
  std::optional<CannelloniError> last_error;
};

class UdpCanBus final : public CanBus {
 public:
  ~UdpCanBus() override;
  UdpCanBus(const UdpCanBus&) = delete;
  UdpCanBus& operator=(const UdpCanBus&) = delete;

  using udp = boost::asio::ip::udp;

  /// A sender: a non-blocking socket connected to @p peer, so that the kernel reports an
  /// absent receiver (ICMP port unreachable) as connection_refused on a later send.
  /// @throws boost::system::system_error
  static std::unique_ptr<UdpCanBus> connect(boost::asio::io_context& io, const udp::endpoint& peer);
  /// A receiver bound to @p local (port 0 picks a free port; see local_endpoint()).
  /// @throws boost::system::system_error
  static std::unique_ptr<UdpCanBus> bind(boost::asio::io_context& io, const udp::endpoint& local);

  std::string_view kind() const override { return "udp"; }
  /// Packs as many frames per datagram as fit in kMaxDatagram bytes; the sequence number goes
  /// up by one per datagram.
  std::error_code send(std::span<const CanFrame> frames) override;
  void start_receive(FrameHandler handler) override;
  void start_on_demand(FrameHandler handler, std::chrono::milliseconds backstop) override;
  std::size_t poll() override;

  udp::endpoint local_endpoint() const { return local_; }
  const UdpCanStats& stats() const { return stats_; }

  /// Keeps datagrams below a 1500-byte Ethernet MTU, as cannelloni does.
  static constexpr std::size_t kMaxDatagram = 1400;

 private:
  explicit UdpCanBus(udp::socket socket)
      : socket_(std::move(socket)), local_(socket_.local_endpoint()) {}
  void receive_next();
  void arm_backstop();
  void on_packet(const std::uint8_t* data, std::size_t n);

  /// poll() reads up to kPollBatch datagrams per system call, each into a kPollSlot-byte slot
  /// of rx_buffer_.
  static constexpr std::size_t kPollBatch = 16;
  static constexpr std::size_t kPollSlot = 4096;
  static_assert(kPollSlot >= kMaxDatagram);

  udp::socket socket_;
  udp::endpoint local_;
  /// On demand, the socket taken out of the io_context (see start_on_demand); -1 before.
  int on_demand_fd_ = -1;
  std::uint8_t tx_sequence_ = 0;
  std::array<std::uint8_t, kMaxDatagram> tx_buffer_{};
  std::vector<std::uint8_t> rx_buffer_ = std::vector<std::uint8_t>(kPollBatch * kPollSlot);
  udp::endpoint rx_from_;
  FrameHandler handler_;
  bool on_demand_ = false;
  std::chrono::milliseconds backstop_period_{};
  std::unique_ptr<boost::asio::steady_timer> backstop_;  ///< on demand only
  std::optional<std::uint8_t> rx_last_sequence_;
  UdpCanStats stats_;
};

}  // namespace tb::can
