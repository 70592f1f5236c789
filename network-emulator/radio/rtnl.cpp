#include "network-emulator/radio/rtnl.hpp"

#include <linux/if_link.h>
#include <net/if.h>
#include <netlink/attr.h>
#include <netlink/errno.h>
#include <netlink/msg.h>
#include <netlink/netlink.h>
#include <netlink/route/link.h>
#include <netlink/route/link/veth.h>

#include <fmt/format.h>

namespace tb::emu::radio {

std::string to_string(const MacAddress& m) {
  return fmt::format("{:02x}:{:02x}:{:02x}:{:02x}:{:02x}:{:02x}", m[0], m[1], m[2], m[3], m[4],
                     m[5]);
}

NetlinkError::NetlinkError(const std::string& what, int nl_error)
    : std::runtime_error(what + ": " + nl_geterror(nl_error)), nl_error_(nl_error) {}

namespace {
struct LinkDeleter {
  void operator()(rtnl_link* l) const { rtnl_link_put(l); }
};
using LinkPtr = std::unique_ptr<rtnl_link, LinkDeleter>;
struct CacheDeleter {
  void operator()(nl_cache* c) const { nl_cache_free(c); }
};
struct AddrDeleter {
  void operator()(nl_addr* a) const { nl_addr_put(a); }
};
}  // namespace

RouteSocket::RouteSocket() : sock_(nl_socket_alloc()) {
  if (!sock_)
    throw NetlinkError("rtnetlink: cannot allocate a socket", -NLE_NOMEM);
  if (int err = nl_connect(sock_, NETLINK_ROUTE); err < 0) {
    nl_socket_free(sock_);
    throw NetlinkError("rtnetlink: cannot connect", err);
  }
}

RouteSocket::~RouteSocket() {
  nl_socket_free(sock_);
}

std::vector<LinkInfo> RouteSocket::links() {
  nl_cache* raw = nullptr;
  if (int err = rtnl_link_alloc_cache(sock_, AF_UNSPEC, &raw); err < 0)
    throw NetlinkError("rtnetlink: cannot list links", err);
  std::unique_ptr<nl_cache, CacheDeleter> cache(raw);
  std::vector<LinkInfo> out;
  for (nl_object* o = nl_cache_get_first(raw); o; o = nl_cache_get_next(o)) {
    auto* l = reinterpret_cast<rtnl_link*>(o);
    LinkInfo info;
    info.index = rtnl_link_get_ifindex(l);
    if (const char* n = rtnl_link_get_name(l))
      info.name = n;
    if (const char* a = rtnl_link_get_ifalias(l))
      info.alias = a;
    info.tx_dropped = rtnl_link_get_stat(l, RTNL_LINK_TX_DROPPED);
    out.push_back(std::move(info));
  }
  return out;
}

void RouteSocket::add_veth(const std::string& name, const std::string& alias,
                           const std::string& peer_name, int peer_netns_fd,
                           const MacAddress& peer_mac, unsigned mtu) {
  if (name.size() >= IFNAMSIZ || peer_name.size() >= IFNAMSIZ)
    throw NetlinkError("veth " + name + "/" + peer_name + ": name longer than " +
                           std::to_string(IFNAMSIZ - 1) + " characters",
                       -NLE_INVAL);
  LinkPtr link(rtnl_link_veth_alloc());
  if (!link)
    throw NetlinkError("veth " + name + ": cannot allocate", -NLE_NOMEM);
  rtnl_link_set_name(link.get(), name.c_str());
  rtnl_link_set_ifalias(link.get(), alias.c_str());
  rtnl_link* peer = rtnl_link_veth_get_peer(link.get());  // owned by link
  rtnl_link_set_name(peer, peer_name.c_str());
  rtnl_link_set_ns_fd(peer, peer_netns_fd);
  // Not IFF_UP here: the kernel opens the peer before it ties the pair together, and a veth
  // without its peer refuses to open (ENOTCONN). Both ends go up after creation.
  std::unique_ptr<nl_addr, AddrDeleter> addr(
      nl_addr_build(AF_LLC, peer_mac.data(), peer_mac.size()));
  rtnl_link_set_addr(peer, addr.get());
  if (mtu != 0) {
    rtnl_link_set_mtu(link.get(), mtu);
    rtnl_link_set_mtu(peer, mtu);
  }
  rtnl_link_put(peer);  // rtnl_link_veth_get_peer took a reference
  if (int err = rtnl_link_add(sock_, link.get(), NLM_F_CREATE | NLM_F_EXCL); err < 0)
    throw NetlinkError("cannot create veth " + name + " with peer " + peer_name + " (" +
                           to_string(peer_mac) + ") in the station's namespace",
                       err);
}

void RouteSocket::add_hub_bridge(const std::string& name, const std::string& alias) {
  if (name.size() >= IFNAMSIZ)
    throw NetlinkError(
        "bridge " + name + ": name longer than " + std::to_string(IFNAMSIZ - 1) + " characters",
        -NLE_INVAL);
  // libnl-route 3.7 has no setters for the bridge's own attributes (IFLA_BR_*): the request is
  // built by hand.
  nl_msg* msg = nlmsg_alloc_simple(RTM_NEWLINK, NLM_F_CREATE | NLM_F_EXCL);
  if (!msg)
    throw NetlinkError("bridge " + name + ": cannot allocate", -NLE_NOMEM);
  ifinfomsg ifi{};
  ifi.ifi_family = AF_UNSPEC;
  int err = nlmsg_append(msg, &ifi, sizeof ifi, NLMSG_ALIGNTO);
  nlattr* info = nullptr;
  nlattr* data = nullptr;
  if (err >= 0)
    err = nla_put_string(msg, IFLA_IFNAME, name.c_str());
  if (err >= 0)
    err = nla_put_string(msg, IFLA_IFALIAS, alias.c_str());
  if (err >= 0 && !(info = nla_nest_start(msg, IFLA_LINKINFO)))
    err = -NLE_NOMEM;
  if (err >= 0)
    err = nla_put_string(msg, IFLA_INFO_KIND, "bridge");
  if (err >= 0 && !(data = nla_nest_start(msg, IFLA_INFO_DATA)))
    err = -NLE_NOMEM;
  if (err >= 0)
    err = nla_put_u32(msg, IFLA_BR_AGEING_TIME, 0);  // learns nothing: floods every frame
  if (err >= 0)
    err = nla_put_u32(msg, IFLA_BR_STP_STATE, 0);
  if (err >= 0)
    err = nla_put_u8(msg, IFLA_BR_MCAST_SNOOPING, 0);
  if (err >= 0) {
    nla_nest_end(msg, data);
    nla_nest_end(msg, info);
    err = nl_send_sync(sock_, msg);  // frees msg
  } else {
    nlmsg_free(msg);
  }
  if (err < 0)
    throw NetlinkError("cannot create bridge " + name, err);
}

void RouteSocket::set_master(const std::string& port, const std::string& master) {
  const int port_index = static_cast<int>(if_nametoindex(port.c_str()));
  const int master_index = static_cast<int>(if_nametoindex(master.c_str()));
  if (port_index == 0 || master_index == 0)
    throw NetlinkError("cannot make " + port + " a port of " + master, -NLE_NODEV);
  if (int err = rtnl_link_enslave_ifindex(sock_, master_index, port_index); err < 0)
    throw NetlinkError("cannot make " + port + " a port of " + master, err);
}

void RouteSocket::set_up(const std::string& name) {
  // By index: libnl's change request does not name the link it changes.
  const int index = static_cast<int>(if_nametoindex(name.c_str()));
  if (index == 0)
    throw NetlinkError("cannot bring " + name + " up", -NLE_NODEV);
  LinkPtr req(rtnl_link_alloc());
  rtnl_link_set_ifindex(req.get(), index);
  LinkPtr change(rtnl_link_alloc());
  rtnl_link_set_flags(change.get(), IFF_UP);
  if (int err = rtnl_link_change(sock_, req.get(), change.get(), 0); err < 0)
    throw NetlinkError("cannot bring " + name + " up", err);
}

bool RouteSocket::remove(const std::string& name) {
  LinkPtr req(rtnl_link_alloc());
  rtnl_link_set_name(req.get(), name.c_str());
  int err = rtnl_link_delete(sock_, req.get());
  if (err == -NLE_NODEV || err == -NLE_OBJ_NOTFOUND)
    return false;
  if (err < 0)
    throw NetlinkError("cannot delete " + name, err);
  return true;
}

}  // namespace tb::emu::radio
