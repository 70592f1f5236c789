#pragma once
/// @file Link management over rtnetlink (libnl-route-3): the veth pairs of the stand-in medium.
/// No shelling out to `ip`.

#include <array>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

struct nl_sock;

namespace tb::emu::radio {

using MacAddress = std::array<std::uint8_t, 6>;
std::string to_string(const MacAddress& mac);

/// A netlink request the kernel refused; what() names the operation, the interface and the
/// kernel's answer.
class NetlinkError : public std::runtime_error {
 public:
  NetlinkError(const std::string& what, int nl_error);
  int nl_error() const { return nl_error_; }

 private:
  int nl_error_;
};

struct LinkInfo {
  int index = 0;
  std::string name;
  std::string alias;  ///< IFLA_IFALIAS, "" when unset
  std::uint64_t tx_dropped =
      0;  ///< frames the link could not pass on (a veth: its peer's queue was full)
};

/// A NETLINK_ROUTE socket of the namespace of the thread that made it.
class RouteSocket {
 public:
  RouteSocket();
  ~RouteSocket();
  RouteSocket(const RouteSocket&) = delete;
  RouteSocket& operator=(const RouteSocket&) = delete;

  std::vector<LinkInfo> links();
  /// A veth pair: @p name here, @p peer_name created directly in the namespace @p peer_netns_fd
  /// (so that it can be called wlan0 whatever this namespace holds) with @p peer_mac; both down.
  /// @p alias labels the local end so that a later run can tell its leftovers. @p mtu, if not
  /// 0, is both ends' MTU. @throws NetlinkError.
  void add_veth(const std::string& name, const std::string& alias, const std::string& peer_name,
                int peer_netns_fd, const MacAddress& peer_mac, unsigned mtu = 0);
  /// A bridge that behaves as a hub: it learns no addresses (ageing time 0), so that every
  /// frame, unicast too, goes out of every port but the one it came in on; no spanning tree,
  /// no multicast snooping. Down; @p alias as for add_veth. @throws NetlinkError.
  void add_hub_bridge(const std::string& name, const std::string& alias);
  /// Makes @p port a port of the bridge @p master. @throws NetlinkError.
  void set_master(const std::string& port, const std::string& master);
  /// Sets IFF_UP. @throws NetlinkError.
  void set_up(const std::string& name);
  /// Deletes the link (a veth takes its peer along). Returns false if it did not exist.
  /// @throws NetlinkError for other failures.
  bool remove(const std::string& name);

 private:
  nl_sock* sock_ = nullptr;
};

}  // namespace tb::emu::radio
