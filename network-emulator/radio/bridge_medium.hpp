#pragma once
/// @file BridgeMedium: the ideal channel in the kernel (issue 21). The veth host ends are the
/// ports of one Linux bridge that learns no addresses, so the kernel hands every frame a
/// station sends to every other station — what the ideal channel decides for every frame —
/// inside the sender's own send, with no program to wake up on the way.
///
/// The program only watches: a PacketTap (TPACKET_V3 ring) shows it each frame after the fact,
/// stamped with the kernel's receive time, for the trace (`medium.rx`, and `medium.frame` via
/// the channel's observer) and the per-link statistics, which the channel counts as it does
/// for the userspace medium. Only an ideal channel without delay or jitter can be left to the
/// bridge (bridge_can_carry()): any other model decides per frame and link in the program.

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>

#include "common/scenario/scenario.hpp"
#include "network-emulator/radio/channel.hpp"
#include "network-emulator/radio/federation.hpp"
#include "network-emulator/radio/medium.hpp"
#include "network-emulator/radio/packet_listener.hpp"
#include "network-emulator/radio/packet_socket.hpp"
#include "network-emulator/radio/packet_tap.hpp"
#include "network-emulator/radio/sender_attribution.hpp"

namespace tb::emu::radio {

/// Whether the kernel bridge gives exactly what @p model decides: every frame to every other
/// station, at once. Otherwise the reason why not.
std::optional<std::string> why_bridge_cannot_carry(const scenario::ChannelModel& model);

class BridgeMedium final : public RemoteFrameSink {
 public:
  /// Makes the bridge @p bridge_name (down until start()) and a tap for frames of
  /// @p ethertype. @p alias labels the bridge as VethRadios labels its pairs, so that a later
  /// run can remove it after a crash. @throws NetlinkError or std::system_error.
  BridgeMedium(boost::asio::io_context& io, const std::string& bridge_name,
               const std::string& alias, std::uint16_t ethertype, Channel& channel);
  /// Deletes the bridge (the veths stay, as VethRadios made them).
  ~BridgeMedium();
  BridgeMedium(const BridgeMedium&) = delete;
  BridgeMedium& operator=(const BridgeMedium&) = delete;

  /// Makes @p host_ifname (a veth host end, up) a port: from now on @p id hears and is heard.
  /// @throws NetlinkError.
  void attach(StationId id, const std::string& host_ifname);
  /// Makes @p host_ifname (a station-host's veth host end) a port carrying the pooled
  /// stations @p ids, told apart by source MAC. The host gets every other port's frames plain,
  /// once, and loops its own stations' frames back to its other stations itself: those never
  /// reach the bridge and are not counted here. @throws NetlinkError.
  void attach_pooled_host(const std::string& host_ifname, std::span<const StationId> ids);
  /// Forgets @p id (its veth is gone or about to be; a gone port leaves the bridge by itself).
  void detach(StationId id);

  /// Sees every frame that came in, with the kernel's receive time (the trace's `medium.rx`).
  void set_frame_observer(FrameObserver o) { observer_ = std::move(o); }
  /// Federation (issue 35): @p to_peers gets each frame a station sends as it comes in, with
  /// the kernel's receive time (read a second time, per frame: the tap hands frames over in
  /// blocks up to kBlockTimeoutMs late, too late for the other nodes); and frames from other
  /// nodes' stations can be handed to deliver_remote(). Before start(). @throws
  /// std::system_error.
  void federate(FrameObserver to_peers);
  /// A frame from another node's station: written once into the bridge, which floods it out
  /// of every port (it learns no addresses) into every local station, pooled hosts too — what
  /// the ideal channel decides; the channel counts (and traces) each link as for a local frame.
  void deliver_remote(StationId from, std::span<const std::uint8_t> frame) override;
  std::uint64_t remote_frames_in() const { return remote_frames_in_; }
  std::uint64_t remote_send_errors() const { return remote_send_errors_; }

  /// Brings the bridge up and starts reading the tap.
  void start();
  /// Reads what the tap holds now; returns the number of frames.
  std::size_t drain();
  /// Reads what the tap holds, the block the kernel is still filling too (it hands that over
  /// within PacketTap::kBlockTimeoutMs): before the statistics are written at exit.
  void drain_all();

  std::uint64_t frames_in() const { return frames_in_; }
  /// Frames the tap missed because its ring was full: they were forwarded, but neither traced
  /// nor counted.
  std::uint64_t tap_drops() { return tap_->drops(); }
  /// Per station: frames its port could not pass on (its veth peer's queue was full), from the
  /// kernel's counters. The only loss of an ideal channel in the kernel.
  std::map<StationId, std::uint64_t> kernel_drops() const;
  const std::string& bridge_name() const { return bridge_; }
  /// Frames from a station-host's port whose source MAC names none of the known stations:
  /// the kernel forwarded them anyway (it cannot tell), but they are neither counted nor
  /// traced.
  std::uint64_t unknown_sender() const { return attribution_.unknown_sender(); }

 private:
  void on_frame(const TappedFrame& f);

  std::string bridge_;
  boost::asio::io_context& io_;
  Channel& channel_;
  std::uint16_t ethertype_;
  std::unique_ptr<PacketListener> federation_reader_;
  std::unique_ptr<PacketSocket> injector_;
  std::uint64_t remote_frames_in_ = 0;
  std::uint64_t remote_send_errors_ = 0;
  std::unique_ptr<PacketTap> tap_;
  boost::asio::posix::stream_descriptor descriptor_;
  SenderAttribution attribution_;
  std::map<StationId, std::string> ifname_of_station_;
  std::vector<StationId> stations_;
  FrameObserver observer_;
  std::uint64_t frames_in_ = 0;
  std::uint64_t unknown_port_ = 0;
};

}  // namespace tb::emu::radio
