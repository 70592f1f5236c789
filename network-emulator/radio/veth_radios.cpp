#include "network-emulator/radio/veth_radios.hpp"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <stdexcept>
#include <system_error>

#include <spdlog/spdlog.h>

#include "common/wire/station_mac.hpp"

namespace tb::emu::radio {

namespace {
constexpr std::string_view kAliasTag = "tb-radio-medium pid=";

bool owner_alive(const std::string& alias) {
  if (!alias.starts_with(kAliasTag))
    return false;
  int pid = 0;
  const char* first = alias.data() + kAliasTag.size();
  const auto [ptr, ec] = std::from_chars(first, alias.data() + alias.size(), pid);
  if (ec != std::errc{} || pid <= 0)
    return false;
  return ::kill(pid, 0) == 0 || errno == EPERM;
}
}  // namespace

std::string owner_alias() {
  return std::string(kAliasTag) + std::to_string(::getpid());
}

MacAddress station_mac(StationId id) {
  return wire::station_mac(id);
}

MacAddress host_mac(std::size_t k) {
  return {0x02, 0x01, 0x00, 0x00, 0x00, static_cast<std::uint8_t>(k)};
}

VethRadios::VethRadios(const std::vector<StationSpec>& stations, const std::string& prefix,
                       const std::vector<PooledHostSpec>& hosts)
    : prefix_(prefix), stations_(stations), hosts_(hosts) {
  if (hosts_.size() > kMaxPooledHosts)
    throw std::runtime_error(std::to_string(hosts_.size()) + " station-hosts: at most " +
                             std::to_string(kMaxPooledHosts) + " (the last byte of their MAC)");
  RouteSocket rtnl;
  try {
    for (const StationSpec& s : stations_)
      add(rtnl, s);
    for (std::size_t k = 0; k < hosts_.size(); ++k)
      add_host(rtnl, k);
  } catch (...) {
    remove_all();
    throw;
  }
}

void VethRadios::add(RouteSocket& rtnl, const StationSpec& s) {
  NetnsFd ns;
  try {
    ns = NetnsFd::open(s.netns);
  } catch (const std::system_error& e) {
    throw std::runtime_error("station " + std::to_string(s.id) + ": " + e.what());
  }
  const std::string name = host_ifname(s.id);
  rtnl.add_veth(name, owner_alias(), kStationIfname, ns.fd(), station_mac(s.id));
  created_.push_back(name);
  rtnl.set_up(name);
  in_netns(ns, [] { RouteSocket(/*station's namespace*/).set_up(kStationIfname); });
  placed_in_[s.id] = ns.identity();
  spdlog::debug("radio: station {}: {} ↔ {}:{} ({})", s.id, name, ns.path(), kStationIfname,
                to_string(station_mac(s.id)));
}

void VethRadios::add_host(RouteSocket& rtnl, std::size_t k) {
  const PooledHostSpec& h = hosts_[k];
  NetnsFd ns;
  try {
    ns = NetnsFd::open(h.netns);
  } catch (const std::system_error& e) {
    throw std::runtime_error("station-host " + std::to_string(k) + ": " + e.what());
  }
  const std::string name = pooled_host_ifname(k);
  rtnl.add_veth(name, owner_alias(), kStationIfname, ns.fd(), host_mac(k), kPooledHostMtu);
  created_.push_back(name);
  rtnl.set_up(name);
  in_netns(ns, [] { RouteSocket(/*the host's namespace*/).set_up(kStationIfname); });
  spdlog::debug("radio: station-host {} ({} stations): {} ↔ {}:{} ({})", k, h.stations.size(), name,
                ns.path(), kStationIfname, to_string(host_mac(k)));
}

std::vector<StationId> VethRadios::moved_stations() const {
  std::vector<StationId> moved;
  for (const StationSpec& s : stations_) {
    const auto placed = placed_in_.find(s.id);
    try {
      if (placed == placed_in_.end() || NetnsFd::open(s.netns).identity() != placed->second)
        moved.push_back(s.id);
    } catch (const std::system_error&) {
      moved.push_back(s.id);  // the name leads nowhere now: the radio is in a dead namespace
    }
  }
  return moved;
}

void VethRadios::reattach(StationId id) {
  const auto spec = std::find_if(stations_.begin(), stations_.end(),
                                 [&](const StationSpec& s) { return s.id == id; });
  if (spec == stations_.end())
    throw std::runtime_error("station " + std::to_string(id) + " has no radio here");
  RouteSocket rtnl;
  const std::string name = host_ifname(id);
  // The pair may be gone already: a veth dies with the namespace of either end.
  rtnl.remove(name);
  std::erase(created_, name);
  placed_in_.erase(id);
  add(rtnl, *spec);
}

VethRadios::~VethRadios() {
  remove_all();
}

void VethRadios::remove_all() noexcept {
  try {
    RouteSocket rtnl;
    for (const std::string& name : created_) {
      try {
        rtnl.remove(name);
      } catch (const std::exception& e) {
        spdlog::error("radio: {}", e.what());
      }
    }
  } catch (const std::exception& e) {
    spdlog::error("radio: cannot remove {} veth pairs: {}", created_.size(), e.what());
  }
  created_.clear();
}

std::vector<std::string> VethRadios::remove_leftovers(const std::string& prefix) {
  RouteSocket rtnl;
  std::vector<std::string> removed;
  for (const LinkInfo& l : rtnl.links()) {
    if (!l.name.starts_with(prefix) || owner_alive(l.alias))
      continue;
    if (rtnl.remove(l.name))
      removed.push_back(l.name);
  }
  return removed;
}

}  // namespace tb::emu::radio
