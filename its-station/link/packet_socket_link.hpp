#pragma once
/// @file The real link: an AF_PACKET socket on the station's radio interface.
///
/// The same code serves a mac80211_hwsim interface in OCB mode and the veth stand-in: both are
/// named wlan0 in the station's namespace and both exchange Ethernet II frames with the packet
/// socket (mac80211 converts 802.11 + LLC/SNAP to and from Ethernet framing), so the layers
/// above cannot tell which one they run on.

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>

#include <boost/asio/io_context.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>

#include "common/util/expected.hpp"
#include "its-station/link/link_layer.hpp"

namespace tb::its::link {

enum class OpenErrorKind {
  kNoSuchInterface,  ///< if_nametoindex failed
  kSocket,           ///< socket(AF_PACKET) failed (EPERM without CAP_NET_RAW)
  kBind,
  kHardwareAddress,  ///< SIOCGIFHWADDR failed or the interface has no 6-byte address
  kSocketOption,     ///< SO_TIMESTAMPNS
};
std::string to_string(OpenErrorKind kind);

struct OpenError {
  OpenErrorKind kind;
  std::string interface;
  int error_number = 0;
  /// E.g. "link: interface 'wlan0': no such interface (No such device)".
  std::string message() const;
};

/// Counters for what the socket saw but did not hand upwards.
struct PacketSocketStats {
  std::uint64_t delivered = 0;
  std::uint64_t ignored_outgoing = 0;    ///< our own frames, looped back to packet sockets
  std::uint64_t ignored_other_host = 0;  ///< unicast to another MAC (promiscuous interface)
  std::uint64_t truncated = 0;           ///< larger than the receive buffer
  std::uint64_t receive_errors = 0;
};

/// What becomes of one frame the socket read (before its Ethernet header is parsed).
enum class RxVerdict { kDeliver, kOutgoing, kOtherHost, kTruncated };
/// @p pkttype the sockaddr_ll's sll_pkttype, @p length the frame's real length (MSG_TRUNC),
/// @p truncated whether the kernel cut it to @p capacity bytes.
RxVerdict classify_received(unsigned char pkttype, std::size_t length, bool truncated,
                            std::size_t capacity);
/// The Ethernet II frame in @p bytes (header and payload, the payload pointing into @p bytes);
/// empty when shorter than a header.
std::optional<ReceivedFrame> parse_ethernet(std::span<const std::uint8_t> bytes,
                                            clock::WallTime rx_time);

class PacketSocketLink final : public LinkLayer {
 public:
  /// Opens a non-blocking packet socket for @p ethertype bound to @p interface, with kernel
  /// receive timestamps. Receiving starts at once, driven by @p io.
  static Expected<std::unique_ptr<PacketSocketLink>, OpenError> open(
      boost::asio::io_context& io, const std::string& interface,
      std::uint16_t ethertype = kEtherTypeGeoNetworking);

  ~PacketSocketLink() override;
  PacketSocketLink(const PacketSocketLink&) = delete;
  PacketSocketLink& operator=(const PacketSocketLink&) = delete;

  MacAddress address() const override { return address_; }
  std::error_code send(const MacAddress& destination, std::uint16_t ethertype,
                       std::span<const std::uint8_t> payload) override;
  void set_receive_handler(ReceiveHandler handler) override { handler_ = std::move(handler); }

  const std::string& interface() const { return interface_; }
  /// The interface's kernel driver as ethtool reports it ("veth" for the stand-in,
  /// "mac80211_hwsim" for a simulated radio), so the program can log which radio it got;
  /// empty if the driver does not say.
  const std::string& driver() const { return driver_; }
  const PacketSocketStats& stats() const { return stats_; }

 private:
  PacketSocketLink(boost::asio::io_context& io, int fd, std::string interface, int ifindex,
                   MacAddress address);
  void arm();
  void drain();

  boost::asio::posix::stream_descriptor socket_;
  std::string interface_;
  int ifindex_;
  MacAddress address_;
  std::string driver_;
  ReceiveHandler handler_;
  PacketSocketStats stats_;
  /// Frames read per system call: a burst of up to this many costs one recvmmsg, and a
  /// shorter one needs no further call to find the socket empty (issue 33: a station hears
  /// its neighbours' CAMs in bursts around each GNSS epoch).
  static constexpr std::size_t kBatch = 16;
  // An Ethernet II header and a full MTU, plus one byte to detect oversized frames.
  static constexpr std::size_t kRxFrameSize = 14 + kMaxPayload + 1;
  std::array<std::array<std::uint8_t, kRxFrameSize>, kBatch> rx_buffers_{};
  std::array<std::uint8_t, 14 + kMaxPayload> tx_buffer_{};
};

}  // namespace tb::its::link
