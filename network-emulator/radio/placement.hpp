#pragma once
/// @file The placement file (issue 35): which swarm node runs which stations, and where that
/// node's radio medium listens for the other media. Written by the stack generator, read by
/// radio-medium (--federation) and the emulator container's entrypoint (shared DESIGN.md of
/// issue 35, contract item 1):
///
///   {"nodes": [{"name": "tb-node1", "medium": "emulator-tb-node1:4730",
///               "stations": [1001, 5001], "pooled": [2001], "station_hosts": 1}, ...]}
///
/// Every station is on exactly one node; node names are unique. Errors name the file, the
/// field (as a JSON path) and the value.

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "network-emulator/radio/channel.hpp"

namespace tb::emu::radio {

class PlacementError : public std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct PlacementNode {
  std::string name;
  std::string medium_host;  ///< a name (resolved at start, retried) or an address
  std::uint16_t medium_port = 0;
  std::vector<StationId> stations;  ///< full stations (vehicles and RSUs)
  std::vector<StationId> pooled;    ///< pooled vehicles of its station-hosts
  unsigned station_hosts = 0;
};

struct Placement {
  std::string source;  ///< the file it came from, for messages
  std::vector<PlacementNode> nodes;

  const PlacementNode* find(const std::string& name) const;
  /// The node that runs station @p id, or null.
  const PlacementNode* node_of(StationId id) const;
};

/// Parses @p text (the JSON) that came from @p source. @throws PlacementError.
Placement parse_placement(const std::string& text, const std::string& source);
/// Reads the file @p path. @throws PlacementError (also when it cannot be read).
Placement load_placement(const std::string& path);

/// Splits "HOST:PORT" (HOST a name, an IPv4 address or [IPv6]); empty when it is not one.
struct HostPort {
  std::string host;
  std::uint16_t port = 0;
};
std::optional<HostPort> parse_host_port(const std::string& text);

}  // namespace tb::emu::radio
