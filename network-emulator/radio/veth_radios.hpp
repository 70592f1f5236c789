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

/// The station's radio MAC: locally administered, unicast, 02:00 then the StationID big-endian,
/// so that a frame's source address names its station in captures.
MacAddress station_mac(StationId id);

inline constexpr const char* kDefaultPrefix = "tbrm";
inline constexpr const char* kStationIfname = "wlan0";

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
  VethRadios(const std::vector<StationSpec>& stations, const std::string& prefix = kDefaultPrefix);
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
  const std::vector<StationSpec>& stations() const { return stations_; }

  /// Deletes interfaces named PREFIX* in this namespace whose owner (recorded in the interface
  /// alias as "tb-radio-medium pid=N") is no longer running, or that carry no owner at all.
  /// Returns their names.
  static std::vector<std::string> remove_leftovers(const std::string& prefix = kDefaultPrefix);

 private:
  void add(RouteSocket& rtnl, const StationSpec& s);
  void remove_all() noexcept;

  std::string prefix_;
  std::vector<StationSpec> stations_;
  std::vector<std::string> created_;
  /// The namespace each station's radio is in (NetnsFd::identity).
  std::map<StationId, std::pair<unsigned long, unsigned long>> placed_in_;
};

}  // namespace tb::emu::radio
