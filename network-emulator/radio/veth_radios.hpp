#pragma once
/// @file The stand-in radios: one veth pair per station, `wlan0` inside the station's namespace,
/// the other end (PREFIX + station id) in the emulator's namespace for the userspace medium.

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "network-emulator/radio/channel.hpp"
#include "network-emulator/radio/netns.hpp"
#include "network-emulator/radio/rtnl.hpp"

namespace tb::emu::radio {

/// A station and the namespace its radio goes into.
struct StationSpec {
  StationId id = 0;
  std::string netns;  ///< name under /run/netns or an absolute path (NetnsFd::open)
};

/// A station-host (issue 33): one namespace, one veth pair, many pooled stations behind it.
struct PooledHostSpec {
  std::string netns;  ///< as StationSpec::netns
  std::vector<StationId> stations;
};

/// The station's radio MAC: locally administered, unicast, 02:00 then the StationID big-endian,
/// so that a frame's source address names its station in captures.
MacAddress station_mac(StationId id);

inline constexpr const char* kDefaultPrefix = "tbrm";
inline constexpr const char* kStationIfname = "wlan0";
/// MTU of a station-host's pair: a pooled delivery (TBPD) lists every receiving station of the
/// host in front of the frame, 4 bytes each; 9000 holds about 1,800 with a 1,500-byte frame.
inline constexpr unsigned kPooledHostMtu = 9000;
/// A station-host's `wlan0`: 02:01:00:00:00:k (locally administered, and no station's MAC,
/// which all start 02:00), k its place among the hosts.
MacAddress host_mac(std::size_t k);
inline constexpr std::size_t kMaxPooledHosts = 256;

/// "tb-radio-medium pid=N": the alias that names the process owning an interface (the host
/// ends of the pairs, the bridge), by which a later run tells a crashed run's leftovers.
std::string owner_alias();

/// Creates the pairs in the constructor and deletes them in the destructor (the peer in the
/// station's namespace goes with its pair).
class VethRadios {
 public:
  /// @p prefix names the host ends (PREFIX + station id, at most 15 characters) and is what a
  /// later run looks for to clean up after a crash. @throws NetlinkError or std::system_error
  /// naming the station; whatever was made before the failure is removed again.
  VethRadios(const std::vector<StationSpec>& stations, const std::string& prefix = kDefaultPrefix,
             const std::vector<PooledHostSpec>& hosts = {});
  ~VethRadios();
  VethRadios(const VethRadios&) = delete;
  VethRadios& operator=(const VethRadios&) = delete;

  /// Stations whose namespace name or path now leads to another namespace than the one their
  /// radio was put in (a station container that restarted gets a new one), or to none.
  std::vector<StationId> moved_stations() const;
  /// Deletes @p id's pair and makes it again in the namespace its name leads to now.
  /// @throws like the constructor; the station then has no radio.
  void reattach(StationId id);

  /// Host-side interface name of @p id.
  std::string host_ifname(StationId id) const { return prefix_ + std::to_string(id); }
  /// Host-side interface name of station-host @p k: PREFIX h k (tbrmh0).
  std::string pooled_host_ifname(std::size_t k) const { return prefix_ + "h" + std::to_string(k); }
  const std::vector<StationSpec>& stations() const { return stations_; }
  const std::vector<PooledHostSpec>& hosts() const { return hosts_; }

  /// Deletes interfaces named PREFIX* in this namespace whose owner (recorded in the interface
  /// alias as "tb-radio-medium pid=N") is no longer running, or that carry no owner at all.
  /// Returns their names.
  static std::vector<std::string> remove_leftovers(const std::string& prefix = kDefaultPrefix);

 private:
  void add(RouteSocket& rtnl, const StationSpec& s);
  void add_host(RouteSocket& rtnl, std::size_t k);
  void remove_all() noexcept;

  std::string prefix_;
  std::vector<StationSpec> stations_;
  std::vector<PooledHostSpec> hosts_;
  std::vector<std::string> created_;
  /// The namespace each station's radio is in (NetnsFd::identity).
  std::map<StationId, std::pair<unsigned long, unsigned long>> placed_in_;
};

}  // namespace tb::emu::radio
