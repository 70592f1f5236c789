#pragma once
/// @file Federation: one node's radio medium joined to the other nodes' media (issue 35). Every
/// frame a local station transmits goes, as one datagram (federation_datagram.hpp) per peer
/// node, to each peer that has a station within the channel's maximum range of the sender
/// (every peer for the ideal channel, or while the sender's position is unknown); a frame from
/// a peer is handed to the local medium as if a local station had sent it, so that the channel
/// model decides per local receiver as for a local frame. Peers that fall silent or cannot be
/// reached are reported once, and again when they are heard from.
///
/// Pure logic: the clock, the datagrams out (FederationTransport) and the frames in
/// (RemoteFrameSink) come from outside; FederationSocket (federation_socket.hpp) is the UDP side.

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "common/clock/clock.hpp"
#include "network-emulator/radio/channel.hpp"
#include "network-emulator/radio/federation_datagram.hpp"
#include "network-emulator/radio/medium.hpp"
#include "network-emulator/radio/placement.hpp"

namespace tb::emu::radio {

/// Where the datagrams for peer nodes go (peer index = Federation::peers() order).
class FederationTransport {
 public:
  virtual ~FederationTransport() = default;
  virtual void send(std::size_t peer, std::span<const std::uint8_t> datagram) = 0;
};

/// Where frames from other nodes' stations go: into this node's stations' radios.
class RemoteFrameSink {
 public:
  virtual ~RemoteFrameSink() = default;
  virtual void deliver_remote(StationId from, std::span<const std::uint8_t> frame) = 0;
};

/// The program's forwarding: the channel decides per local receiver (Medium::on_remote_frame).
class MediumRemoteSink final : public RemoteFrameSink {
 public:
  explicit MediumRemoteSink(Medium& medium) : medium_(medium) {}
  void deliver_remote(StationId from, std::span<const std::uint8_t> frame) override {
    medium_.on_remote_frame(from, frame);
  }

 private:
  Medium& medium_;
};

/// A peer's liveness changed.
struct PeerEvent {
  std::string node;
  bool up = false;
  std::string why;
};

class Federation {
 public:
  /// Heartbeats go out this often (Federation::tick()); a peer not heard from for
  /// kSilenceLimit is down.
  static constexpr clock::Duration kHeartbeatInterval = std::chrono::milliseconds(500);
  static constexpr clock::Duration kSilenceLimit = std::chrono::seconds(3);

  /// @p self must be a node of @p placement (PlacementError naming it otherwise). @p channel
  /// decides the range and @p positions holds every station's position (the state stream is
  /// relayed to every node); a remote sender the table does not know is placed where its
  /// datagram says.
  Federation(const Placement& placement, const std::string& self, const Channel& channel,
             PositionTable& positions, const clock::Clock& clock, FederationTransport& transport,
             RemoteFrameSink& sink);

  const std::string& self() const { return self_; }
  /// The other nodes, in placement order; their index is the transport's peer index.
  const std::vector<PlacementNode>& peers() const { return peers_; }

  /// The peers a frame from @p from must go to: those with a station within the channel's
  /// maximum range of @p from, or a station without a known position; every peer when the
  /// channel is ideal or @p from's position is unknown. Indices in ascending order.
  void peers_for(StationId from, std::vector<std::size_t>& out);

  /// A local station's frame (@p tx_unix_ns: when the kernel received it from the station;
  /// 0: now). Sent to peers_for(@p from).
  void on_local_frame(StationId from, std::span<const std::uint8_t> frame, std::int64_t tx_unix_ns);
  /// A datagram from the federation socket, received at @p rx_unix_ns (0: now). Malformed
  /// ones, and frames whose sender is not a station of the peer that says it sent them, are
  /// counted and dropped.
  void on_datagram(std::span<const std::uint8_t> bytes, std::int64_t rx_unix_ns,
                   std::int64_t kernel_rx_unix_ns = 0);

  /// Every kHeartbeatInterval: heartbeats to every peer, and peers silent for kSilenceLimit
  /// are declared down.
  void tick();
  /// The transport could not send to @p peer (ICMP unreachable, a name that does not
  /// resolve): the peer is down now, for @p why.
  void on_send_error(std::size_t peer, const std::string& why);

  void set_peer_events(std::function<void(const PeerEvent&)> f) { events_ = std::move(f); }
  /// Sees every frame from a peer before it is delivered (the trace's `medium.hop`), with the
  /// time it was read and the kernel's receive stamp of its datagram (0 when there is none).
  using HopObserver = std::function<void(const FederationDatagram&, std::int64_t rx_unix_ns,
                                         std::int64_t kernel_rx_unix_ns)>;
  void set_hop_observer(HopObserver f) { hop_observer_ = std::move(f); }
  /// Sees every malformed or foreign datagram, with the reason (logged once by the program).
  using RejectObserver = std::function<void(std::string_view why)>;
  void set_reject_observer(RejectObserver f) { reject_observer_ = std::move(f); }

  bool peer_up(std::size_t peer) const { return state_[peer].up; }
  std::uint64_t frames_out() const { return frames_out_; }        ///< local frames federated
  std::uint64_t datagrams_out() const { return datagrams_out_; }  ///< frame datagrams sent
  std::uint64_t peers_skipped() const { return peers_skipped_; }  ///< no station in range
  std::uint64_t frames_in() const { return frames_in_; }          ///< remote frames delivered
  std::uint64_t rejected() const { return rejected_; }            ///< malformed or foreign

 private:
  struct PeerState {
    clock::SteadyTime last_heard{};
    bool up = false;
    bool reported_down = false;  ///< said once until heard from again
    std::string last_error;
  };
  void heard_from(std::size_t peer);
  void down(std::size_t peer, const std::string& why);
  void reject(std::string_view why);
  std::int64_t now_ns() const { return clock::to_unix_ns(clock_.wall_now()); }

  std::string self_;
  const Channel& channel_;
  PositionTable& positions_;
  const clock::Clock& clock_;
  FederationTransport& transport_;
  RemoteFrameSink& sink_;
  std::vector<PlacementNode> peers_;
  std::unordered_map<StationId, std::size_t> peer_of_station_;
  std::unordered_map<std::string, std::size_t> peer_by_name_;
  std::vector<PeerState> state_;
  /// Peer stations with no position yet: their node is sent every frame until they have one.
  std::vector<StationId> unplaced_;
  std::function<void(const PeerEvent&)> events_;
  HopObserver hop_observer_;
  RejectObserver reject_observer_;
  // Reused per frame.
  std::vector<StationId> reachable_;
  std::vector<std::size_t> chosen_;
  std::vector<bool> mark_;
  std::vector<std::uint8_t> datagram_;
  std::uint64_t frames_out_ = 0;
  std::uint64_t datagrams_out_ = 0;
  std::uint64_t peers_skipped_ = 0;
  std::uint64_t frames_in_ = 0;
  std::uint64_t rejected_ = 0;
};

}  // namespace tb::emu::radio
