#include "network-emulator/radio/federation.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace tb::emu::radio {

Federation::Federation(const Placement& placement, const std::string& self, const Channel& channel,
                       PositionTable& positions, const clock::Clock& clock,
                       FederationTransport& transport, RemoteFrameSink& sink)
    : self_(self),
      channel_(channel),
      positions_(positions),
      clock_(clock),
      transport_(transport),
      sink_(sink) {
  if (!placement.find(self))
    throw PlacementError(
        fmt::format("placement {}: --node {}: no node of that name", placement.source, self));
  for (const auto& n : placement.nodes) {
    if (n.name == self)
      continue;
    const std::size_t k = peers_.size();
    peers_.push_back(n);
    peer_by_name_[n.name] = k;
    for (const auto* list : {&n.stations, &n.pooled})
      for (const StationId id : *list) {
        peer_of_station_[id] = k;
        unplaced_.push_back(id);
      }
  }
  // Silent from the start until the first datagram: a peer that never answers is reported
  // kSilenceLimit after start.
  state_.resize(peers_.size());
  for (auto& s : state_)
    s.last_heard = clock_.steady_now();
  mark_.resize(peers_.size());
}

void Federation::peers_for(StationId from, std::vector<std::size_t>& out) {
  out.clear();
  if (!channel_.reachable(from, reachable_)) {
    for (std::size_t k = 0; k < peers_.size(); ++k)
      out.push_back(k);
    return;
  }
  std::fill(mark_.begin(), mark_.end(), false);
  for (const StationId id : reachable_)
    if (const auto it = peer_of_station_.find(id); it != peer_of_station_.end())
      mark_[it->second] = true;
  // A station with no position cannot be ruled out (as Medium offers it every frame).
  std::erase_if(unplaced_, [this](StationId id) { return channel_.has_position(id); });
  for (const StationId id : unplaced_)
    mark_[peer_of_station_.at(id)] = true;
  for (std::size_t k = 0; k < peers_.size(); ++k)
    if (mark_[k])
      out.push_back(k);
}

void Federation::on_local_frame(StationId from, std::span<const std::uint8_t> frame,
                                std::int64_t tx_unix_ns) {
  if (peers_.empty())
    return;
  peers_for(from, chosen_);
  peers_skipped_ += peers_.size() - chosen_.size();
  if (chosen_.empty())
    return;
  const auto p = positions_.position(from);
  if (!encode_federated_frame(self_, from, p ? &p->position : nullptr,
                              tx_unix_ns != 0 ? tx_unix_ns : now_ns(), frame, datagram_)) {
    reject("a local frame longer than a federation datagram carries (not federated)");
    return;
  }
  ++frames_out_;
  for (const std::size_t k : chosen_) {
    transport_.send(k, datagram_);
    ++datagrams_out_;
  }
}

void Federation::on_datagram(std::span<const std::uint8_t> bytes, std::int64_t rx_unix_ns,
                             std::int64_t kernel_rx_unix_ns) {
  const auto d = decode_federation_datagram(bytes);
  if (!d) {
    reject(to_string(d.error()));
    return;
  }
  const auto peer = peer_by_name_.find(std::string(d->node));
  if (peer == peer_by_name_.end()) {
    reject(fmt::format("a datagram from node \"{}\", which is no peer of {} in the placement",
                       d->node, self_));
    return;
  }
  heard_from(peer->second);
  if (d->kind == FederationKind::kHeartbeat)
    return;
  const auto owner = peer_of_station_.find(d->sender);
  if (owner == peer_of_station_.end() || owner->second != peer->second) {
    reject(fmt::format("node {} sent a frame of station {}, which the placement puts elsewhere",
                       d->node, d->sender));
    return;
  }
  // The channel decides with this node's table, as for a local frame, so that a link is
  // judged the same whichever node its sender runs on; the datagram's position stands in only
  // for a sender this table has never placed.
  if (d->has_position && !positions_.position(d->sender))
    positions_.set(d->sender, StationPosition{d->position, -1});
  if (hop_observer_)
    hop_observer_(*d, rx_unix_ns != 0 ? rx_unix_ns : now_ns(), kernel_rx_unix_ns);
  ++frames_in_;
  sink_.deliver_remote(d->sender, d->frame);
}

void Federation::tick() {
  if (peers_.empty())
    return;
  if (encode_federation_heartbeat(self_, now_ns(), datagram_))
    for (std::size_t k = 0; k < peers_.size(); ++k)
      transport_.send(k, datagram_);
  const auto now = clock_.steady_now();
  for (std::size_t k = 0; k < peers_.size(); ++k) {
    PeerState& s = state_[k];
    if (!s.reported_down && now - s.last_heard >= kSilenceLimit) {
      const auto secs = std::chrono::duration<double>(now - s.last_heard).count();
      down(k, s.last_error.empty()
                  ? fmt::format("nothing heard for {:.1f} s (no frame, no heartbeat)", secs)
                  : fmt::format("{}; nothing heard for {:.1f} s", s.last_error, secs));
    }
  }
}

void Federation::on_send_error(std::size_t peer, const std::string& why) {
  state_.at(peer).last_error = why;
  down(peer, why);
}

void Federation::heard_from(std::size_t peer) {
  PeerState& s = state_[peer];
  s.last_heard = clock_.steady_now();
  s.last_error.clear();
  if (s.up)
    return;
  const bool was_down = s.reported_down;
  s.up = true;
  s.reported_down = false;
  if (events_)
    events_({peers_[peer].name, true, was_down ? "heard from again" : "first heard from"});
}

void Federation::down(std::size_t peer, const std::string& why) {
  PeerState& s = state_[peer];
  s.up = false;
  if (s.reported_down)
    return;
  s.reported_down = true;
  if (events_)
    events_({peers_[peer].name, false, why});
}

void Federation::reject(std::string_view why) {
  ++rejected_;
  if (reject_observer_)
    reject_observer_(why);
}

}  // namespace tb::emu::radio
