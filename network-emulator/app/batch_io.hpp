#pragma once
/// @file The program's feeds on BatchSender: a UDP socket per network namespace and receiver,
/// connected to it (the stations' feeds), or unconnected per namespace and address family
/// (`--forward`); a DatagramSink (NMEA) or a CanBus (cannelloni) per station and feed on it.

#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "common/can/can_bus.hpp"
#include "network-emulator/app/batch_sender.hpp"
#include "network-emulator/app/emulator.hpp"

namespace tb::emu {

/// BatchSocketOps on a real socket: sendmmsg, and recvmsg(MSG_ERRQUEUE) for the errors.
class UdpBatchSocket final : public BatchSocketOps {
 public:
  /// A non-blocking UDP socket of @p family with IP_RECVERR (IPV6_RECVERR), made inside
  /// /run/netns/@p netns when that is not empty, connected to @p connect_to if given.
  /// @throws std::system_error when the namespace or the socket cannot be had.
  UdpBatchSocket(int family, const std::string& netns, const Destination* connect_to = nullptr);
  ~UdpBatchSocket() override;
  UdpBatchSocket(const UdpBatchSocket&) = delete;
  UdpBatchSocket& operator=(const UdpBatchSocket&) = delete;

  int send_many(std::span<mmsghdr> msgs) override;
  std::optional<QueuedError> read_error() override;
  int fd() const { return fd_; }

 private:
  int fd_ = -1;
};

/// A station's NMEA feed: one sink of a BatchSender.
class BatchedDatagramSink final : public DatagramSink {
 public:
  BatchedDatagramSink(BatchSender& sender, const Destination& to)
      : sender_(sender), sink_(sender.add_sink(to)) {}
  std::error_code send(std::span<const std::uint8_t> datagram) override {
    return sender_.send(sink_, datagram);
  }

 private:
  BatchSender& sender_;
  BatchSender::Sink sink_;
};

/// A station's CAN bus as cannelloni over UDP (common/can/cannelloni.hpp) on a BatchSender:
/// the same datagrams as tb::can::UdpCanBus, batched. Send only.
class BatchedCanBus final : public tb::can::CanBus {
 public:
  BatchedCanBus(BatchSender& sender, const Destination& to)
      : sender_(sender), sink_(sender.add_sink(to)) {}
  std::string_view kind() const override { return "udp"; }
  /// Frames per datagram as UdpCanBus packs them (under 1400 bytes); the sequence number goes
  /// up by one per datagram.
  std::error_code send(std::span<const tb::can::CanFrame> frames) override;
  void start_receive(FrameHandler) override {}

 private:
  BatchSender& sender_;
  BatchSender::Sink sink_;
  std::uint8_t sequence_ = 0;
  std::array<std::uint8_t, 1400> buffer_{};
};

/// One BatchSender per (network namespace, address family), made when first asked for.
class BatchSenders {
 public:
  /// The sender whose socket lives in @p netns ("" = this process's namespace).
  /// @throws std::system_error as UdpBatchSocket.
  BatchSender& get(const std::string& netns, int family);
  /// The sender whose socket lives in @p netns and is connected to @p to (its sinks must all
  /// send there). A connected socket keeps its route: with a namespace per station, the route
  /// lookup of an unconnected socket was 9 % of the emulator's time (network-emulator/README).
  /// @throws std::system_error as UdpBatchSocket.
  BatchSender& get_connected(const std::string& netns, const Destination& to);
  /// Flushes every sender that has something queued.
  void flush();
  /// Totals over all senders.
  BatchStats stats() const;
  std::size_t sockets() const { return senders_.size() + connected_.size(); }

 private:
  struct Entry {
    std::unique_ptr<UdpBatchSocket> socket;
    std::unique_ptr<BatchSender> sender;
  };
  std::map<std::pair<std::string, int>, Entry> senders_;
  std::map<std::pair<std::string, std::string>, Entry> connected_;
  std::vector<BatchSender*> all_;
};

}  // namespace tb::emu
