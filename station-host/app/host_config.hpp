#pragma once
/// @file station-host's command line checked against the scenario: which stations it runs,
/// where the states come from, how the medium forwards, where each station's PKI files are.
/// Every refusal names the option (or file) and the value.

#include <cstdint>
#include <filesystem>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "common/scenario/scenario.hpp"

namespace tb::host {

/// A command line or scenario the host cannot run with; the message says which and why.
struct ConfigError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// `udp://ADDR:PORT` (IPv4 dotted quad, or [IPv6]).
struct UdpEndpoint {
  std::string address;
  std::uint16_t port = 0;
};
/// @throws ConfigError naming --states and the value.
UdpEndpoint parse_states_url(std::string_view url);

/// "3004,3007": the ids, in order. @throws ConfigError for an empty list, a non-number or a
/// repeated id.
std::vector<std::uint32_t> parse_station_list(std::string_view list);

/// The vehicles of @p ids. @throws ConfigError when an id is not a vehicle of the scenario or
/// its vehicle is not `"station": {"kind": "pooled"}`.
std::vector<const scenario::Vehicle*> pooled_vehicles(const scenario::Scenario& scenario,
                                                      std::span<const std::uint32_t> ids);

enum class Forwarding { kKernel, kUser };
/// `--forwarding auto|kernel|user` resolved as radio-medium resolves it: auto is kernel when
/// the kernel bridge can carry the channel (@p why_not_kernel empty). @throws ConfigError for
/// another value, and for kernel when the bridge cannot carry the channel.
Forwarding resolve_forwarding(std::string_view option, const std::string& why_not_kernel);

/// DIR/<station id>/, which must be a directory: what `its-pki export` gives a full station.
/// @throws ConfigError naming the station and the path.
std::filesystem::path station_pki_dir(const std::filesystem::path& pki_dir,
                                      std::uint32_t station_id);

}  // namespace tb::host
