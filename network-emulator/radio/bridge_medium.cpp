#include "network-emulator/radio/bridge_medium.hpp"

#include <net/if.h>
#include <poll.h>
#include <unistd.h>

#include <cerrno>
#include <fstream>
#include <system_error>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "network-emulator/radio/read_loop.hpp"
#include "network-emulator/radio/rtnl.hpp"

namespace tb::emu::radio {

std::optional<std::string> why_bridge_cannot_carry(const scenario::ChannelModel& model) {
  if (model.kind != scenario::ChannelModel::Kind::kIdeal)
    return fmt::format("the {} channel decides per frame and link", to_string(model.kind));
  if (model.delay_ms != 0.0 || model.jitter_ms != 0.0)
    return fmt::format("the ideal channel has a delay of {} ms and a jitter of {} ms",
                       model.delay_ms, model.jitter_ms);
  return std::nullopt;
}

namespace {
int ifindex_of(const std::string& name) {
  return static_cast<int>(if_nametoindex(name.c_str()));
}

/// The bridge's own IPv6 (a link-local address, its router and listener reports) would be sent
/// into every station as frames on the air. Best effort: a kernel without IPv6 has none.
void disable_ipv6(const std::string& ifname) {
  std::ofstream f("/proc/sys/net/ipv6/conf/" + ifname + "/disable_ipv6");
  f << "1\n";
}
}  // namespace

BridgeMedium::BridgeMedium(boost::asio::io_context& io, const std::string& bridge_name,
                           const std::string& alias, std::uint16_t ethertype, Channel& channel)
    : bridge_(bridge_name), io_(io), channel_(channel), ethertype_(ethertype), descriptor_(io) {
  RouteSocket rtnl;
  rtnl.add_hub_bridge(bridge_, alias);
  try {
    disable_ipv6(bridge_);
    // The frames the bridge passes up to its own interface (every broadcast) are copies of
    // frames already tapped on their port.
    tap_ = std::make_unique<PacketTap>(ethertype, ifindex_of(bridge_));
  } catch (...) {
    rtnl.remove(bridge_);
    throw;
  }
}

BridgeMedium::~BridgeMedium() {
  try {
    RouteSocket().remove(bridge_);
  } catch (const std::exception& e) {
    spdlog::error("radio: {}", e.what());
  }
}

void BridgeMedium::attach(StationId id, const std::string& host_ifname) {
  RouteSocket().set_master(host_ifname, bridge_);
  detach(id);
  attribution_.add_station_port(ifindex_of(host_ifname), id);
  ifname_of_station_[id] = host_ifname;
  stations_.push_back(id);
}

void BridgeMedium::attach_pooled_host(const std::string& host_ifname,
                                      std::span<const StationId> ids) {
  RouteSocket().set_master(host_ifname, bridge_);
  const int ifindex = ifindex_of(host_ifname);
  for (const StationId id : ids) {
    detach(id);
    attribution_.add_pooled(ifindex, id);
    stations_.push_back(id);
  }
}

void BridgeMedium::detach(StationId id) {
  std::erase(stations_, id);
  ifname_of_station_.erase(id);
  attribution_.remove_station(id);
}

void BridgeMedium::federate(FrameObserver to_peers) {
  federation_reader_ = std::make_unique<PacketListener>(
      io_, ethertype_, ifindex_of(bridge_),
      [this, to_peers = std::move(to_peers)](int ifindex, std::span<const std::uint8_t> frame,
                                             std::int64_t unix_ns) {
        // The tap counts the frames of unknown senders; this reader only passes frames on.
        if (const auto from = attribution_.peek_sender(ifindex, frame))
          to_peers(*from, frame, unix_ns);
      });
  // Protocol 0: sends only, receives nothing.
  injector_ = std::make_unique<PacketSocket>(bridge_, 0);
}

void BridgeMedium::deliver_remote(StationId from, std::span<const std::uint8_t> frame) {
  ++remote_frames_in_;
  for (const StationId to : stations_)
    channel_.decide(from, to);
  if (injector_ && !injector_->send(frame) && remote_send_errors_++ == 0)
    spdlog::warn("radio: cannot write a remote frame into bridge {}: {} (counted, said once)",
                 bridge_, std::system_category().message(errno));
}

void BridgeMedium::start() {
  RouteSocket().set_up(bridge_);
  if (federation_reader_)
    federation_reader_->start();
  descriptor_.assign(::dup(tap_->fd()));
  drain_when_readable(descriptor_, [this] { drain(); });
}

std::size_t BridgeMedium::drain() {
  return tap_->drain([this](const TappedFrame& f) { on_frame(f); });
}

void BridgeMedium::drain_all() {
  drain();
  pollfd p{tap_->fd(), POLLIN, 0};
  while (::poll(&p, 1, 2 * static_cast<int>(PacketTap::kBlockTimeoutMs)) > 0 && drain() > 0) {
  }
}

void BridgeMedium::on_frame(const TappedFrame& f) {
  if (!attribution_.is_port(f.ifindex)) {
    // Another interface of this namespace with the same ethertype, or a port detached since.
    if (unknown_port_++ == 0)
      spdlog::debug("radio: frame on interface {}, which is no station's port (ignored)",
                    f.ifindex);
    return;
  }
  const auto sender = attribution_.sender(f.ifindex, f.bytes);
  if (!sender) {
    if (attribution_.unknown_sender() == 1)
      spdlog::warn(
          "radio: a frame on a station-host's port (interface {}) from a MAC address that names "
          "none of its stations (forwarded by the kernel, not counted: unknown_sender, "
          "reported once)",
          f.ifindex);
    return;
  }
  const StationId from = *sender;
  ++frames_in_;
  if (observer_)
    observer_(from, f.bytes, f.unix_ns);
  // The kernel has delivered it to every other port; the channel counts (and traces) what it
  // would have decided, which for this channel is exactly that. Not to the sender's own
  // host's stations: the bridge sends nothing back out of the port it came in on, and the
  // host hands them the frame itself.
  const int host = attribution_.host_port_of(from);
  for (const StationId to : stations_)
    if (to != from && (host == 0 || attribution_.host_port_of(to) != host))
      channel_.decide(from, to);
}

std::map<StationId, std::uint64_t> BridgeMedium::kernel_drops() const {
  std::map<StationId, std::uint64_t> out;
  std::map<std::string, std::uint64_t> by_name;
  for (const LinkInfo& l : RouteSocket().links())
    by_name[l.name] = l.tx_dropped;
  for (const auto& [id, name] : ifname_of_station_)
    if (const auto it = by_name.find(name); it != by_name.end())
      out[id] = it->second;
  return out;
}

}  // namespace tb::emu::radio
