#pragma once
/// @file SenderAttribution: which station put a frame on the air (issue 33). A full station's
/// port carries its own station's frames; a station-host's port carries the frames of many
/// pooled stations, told apart by their source MAC (02:00 + StationID, station_mac()). Pure
/// logic, shared by the kernel's forwarding (BridgeMedium) and the program's (VethPorts).

#include <cstdint>
#include <optional>
#include <span>
#include <unordered_map>

#include "network-emulator/radio/channel.hpp"

namespace tb::emu::radio {

/// The station whose radio MAC (station_mac()) @p mac is, whether or not it exists.
std::optional<StationId> station_of_mac(std::span<const std::uint8_t, 6> mac);

class SenderAttribution {
 public:
  /// @p ifindex is @p id's own port (a full station).
  void add_station_port(int ifindex, StationId id);
  /// @p ifindex is a station-host's port and @p id one of its pooled stations.
  void add_pooled(int ifindex, StationId id);
  /// Forgets @p id (its port too if it was a full station's).
  void remove_station(StationId id);

  /// The sending station of @p frame (an Ethernet frame) that came in on @p ifindex: the
  /// station its source MAC names where that is a known station, else the full station whose
  /// port it is. Empty when @p ifindex is no port (ignored), or when it is a host's port and
  /// the source MAC names none of the known stations (counted in unknown_sender()).
  std::optional<StationId> sender(int ifindex, std::span<const std::uint8_t> frame);
  /// The same, without counting an unknown sender (a second reader of the same frames).
  std::optional<StationId> peek_sender(int ifindex, std::span<const std::uint8_t> frame) const;

  bool is_port(int ifindex) const {
    return station_of_port_.contains(ifindex) || host_ports_.contains(ifindex);
  }
  /// The host port of pooled station @p id, or 0 if it is not pooled.
  int host_port_of(StationId id) const {
    const auto it = pooled_.find(id);
    return it == pooled_.end() ? 0 : it->second;
  }
  /// Frames from a host's port whose source MAC named no known station (dropped).
  std::uint64_t unknown_sender() const { return unknown_sender_; }

 private:
  std::unordered_map<int, StationId> station_of_port_;
  std::unordered_map<StationId, int> port_of_station_;
  std::unordered_map<StationId, int> pooled_;        ///< pooled station → its host's port
  std::unordered_map<int, std::size_t> host_ports_;  ///< host port → how many stations
  std::uint64_t unknown_sender_ = 0;
};

}  // namespace tb::emu::radio
