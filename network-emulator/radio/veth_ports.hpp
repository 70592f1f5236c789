#pragma once
/// @file VethPorts: the userspace medium's I/O on the veth host ends, for channels that decide
/// per frame and link (loss, delay: everything the kernel bridge cannot carry, bridge_medium.hpp).
///
/// Two AF_PACKET sockets for all stations instead of one per station: one receives what every
/// station sends (up to kBatch frames per recvmmsg, each with the kernel's receive time), the
/// other sends the medium's deliveries, each to its receiver's interface, in one sendmmsg per
/// batch: at the end of each wake-up that read frames, and once the io_context has run the
/// delayed deliveries that fall due together. At 50 stations one CAM makes 49 deliveries: one
/// system call instead of 49.

#include <linux/if_packet.h>
#include <sys/socket.h>

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>

#include "network-emulator/radio/medium.hpp"
#include "network-emulator/radio/sender_attribution.hpp"

namespace tb::emu::radio {

class VethPorts {
 public:
  static constexpr std::size_t kBatch = 64;         ///< frames per recvmmsg
  static constexpr std::size_t kMaxFrame = 4096;    ///< a veth's MTU is 1500
  static constexpr std::size_t kMaxPending = 1024;  ///< deliveries per sendmmsg (UIO_MAXIOV)

  /// Receives frames of @p ethertype (kEthertypeAll: every frame) on every interface of the
  /// calling thread's namespace that is a port, and hands them to @p medium.
  /// @throws std::system_error.
  VethPorts(boost::asio::io_context& io, std::uint16_t ethertype, Medium& medium);
  ~VethPorts();
  VethPorts(const VethPorts&) = delete;
  VethPorts& operator=(const VethPorts&) = delete;

  /// Makes @p host_ifname (a veth host end) @p id's port and attaches it to the medium.
  /// @throws std::system_error when there is no such interface.
  void attach(StationId id, const std::string& host_ifname);
  /// Makes @p host_ifname (a station-host's veth host end, VethRadios::pooled_host_ifname) the
  /// port of the pooled stations @p ids: their frames are told apart by source MAC, and what
  /// the medium delivers to any of them goes out as one pooled delivery (TBPD,
  /// common/wire/pooled_delivery.hpp) per frame and due time, split only where the receivers
  /// would not fit into @p mtu. @throws std::system_error when there is no such interface.
  void attach_pooled_host(const std::string& host_ifname, std::span<const StationId> ids,
                          unsigned mtu);
  /// Detaches @p id (full or pooled) from the medium; deliveries already queued are still sent.
  void detach(StationId id);
  void start();

  std::uint64_t received() const { return received_; }
  std::uint64_t sent() const { return sent_; }
  std::uint64_t send_calls() const { return send_calls_; }
  std::uint64_t send_errors() const { return send_errors_; }
  std::uint64_t receive_errors() const { return receive_errors_; }
  /// Frames from a station-host's port whose source MAC names no known station (dropped).
  std::uint64_t unknown_sender() const { return attribution_.unknown_sender(); }
  std::uint64_t pooled_frames_sent() const { return pooled_frames_; }

 private:
  class Port final : public FrameSink {
   public:
    Port(VethPorts& owner, int ifindex) : owner_(owner), ifindex_(ifindex) {}
    void transmit(std::span<const std::uint8_t> frame) override { owner_.queue(ifindex_, frame); }

   private:
    VethPorts& owner_;
    int ifindex_;
  };
  class HostPort final : public PooledSink {
   public:
    HostPort(VethPorts& owner, int ifindex, unsigned mtu)
        : owner_(owner), ifindex_(ifindex), mtu_(mtu) {}
    void transmit(std::span<const StationId> receivers,
                  std::span<const std::uint8_t> frame) override {
      owner_.queue_pooled(ifindex_, mtu_, receivers, frame);
    }

   private:
    VethPorts& owner_;
    int ifindex_;
    unsigned mtu_;
  };
  struct Pending {
    int ifindex;
    std::size_t offset, size;  // in arena_
  };

  void drain();
  void drain_batches();
  void queue(int ifindex, std::span<const std::uint8_t> frame);
  void queue_pooled(int ifindex, unsigned mtu, std::span<const StationId> receivers,
                    std::span<const std::uint8_t> frame);
  void flush();

  boost::asio::io_context& io_;
  Medium& medium_;
  int rx_fd_ = -1;
  int tx_fd_ = -1;
  boost::asio::posix::stream_descriptor descriptor_;
  SenderAttribution attribution_;
  std::map<StationId, std::unique_ptr<Port>> ports_;
  std::map<int, std::unique_ptr<HostPort>> hosts_;  ///< by ifindex
  std::vector<StationId> pooled_;                   ///< attached behind a host
  // Receive batch, reused.
  std::vector<std::array<std::uint8_t, kMaxFrame>> rx_buffers_;
  std::vector<mmsghdr> rx_headers_;
  std::vector<iovec> rx_iovecs_;
  std::vector<sockaddr_storage> rx_from_;
  std::vector<std::array<char, 64>> rx_control_;
  // Send batch, reused.
  std::vector<std::uint8_t> arena_;
  std::vector<Pending> pending_;
  std::vector<sockaddr_ll> tx_to_;
  std::vector<iovec> tx_iovecs_;
  std::vector<mmsghdr> tx_headers_;
  bool flush_posted_ = false;
  bool draining_ = false;
  std::uint64_t received_ = 0;
  std::uint64_t sent_ = 0;
  std::uint64_t send_calls_ = 0;
  std::uint64_t send_errors_ = 0;
  std::uint64_t receive_errors_ = 0;
  std::uint64_t pooled_frames_ = 0;
  std::uint64_t oversized_ = 0;
};

}  // namespace tb::emu::radio
