#include "station-host/app/host_config.hpp"

#include <charconv>
#include <set>

#include <fmt/format.h>
#include <boost/asio/ip/address.hpp>

namespace tb::host {

UdpEndpoint parse_states_url(std::string_view url) {
  auto fail = [&](std::string_view why) {
    return ConfigError(fmt::format("--states '{}': {} (expected udp://ADDR:PORT)", url, why));
  };
  constexpr std::string_view kScheme = "udp://";
  if (!url.starts_with(kScheme))
    throw fail("not a udp:// URL");
  std::string_view rest = url.substr(kScheme.size());
  const auto colon = rest.rfind(':');
  if (colon == std::string_view::npos)
    throw fail("no port");
  std::string_view host = rest.substr(0, colon);
  const std::string_view port = rest.substr(colon + 1);
  if (host.size() >= 2 && host.front() == '[' && host.back() == ']')
    host = host.substr(1, host.size() - 2);
  boost::system::error_code ec;
  boost::asio::ip::make_address(std::string(host), ec);
  if (host.empty() || ec)
    throw fail(fmt::format("'{}' is not an IP address", host));
  unsigned value = 0;
  const auto [end, err] = std::from_chars(port.data(), port.data() + port.size(), value);
  if (port.empty() || err != std::errc{} || end != port.data() + port.size() || value == 0 ||
      value > 65535)
    throw fail(fmt::format("'{}' is not a port (1..65535)", port));
  return {std::string(host), static_cast<std::uint16_t>(value)};
}

std::vector<std::uint32_t> parse_station_list(std::string_view list) {
  std::vector<std::uint32_t> ids;
  std::set<std::uint32_t> seen;
  std::size_t pos = 0;
  while (pos <= list.size()) {
    const auto comma = std::min(list.find(',', pos), list.size());
    const std::string_view item = list.substr(pos, comma - pos);
    std::uint32_t id = 0;
    const auto [end, err] = std::from_chars(item.data(), item.data() + item.size(), id);
    if (item.empty() || err != std::errc{} || end != item.data() + item.size())
      throw ConfigError(fmt::format("--stations '{}': '{}' is not a station id", list, item));
    if (!seen.insert(id).second)
      throw ConfigError(fmt::format("--stations '{}': station {} is listed twice", list, id));
    ids.push_back(id);
    pos = comma + 1;
  }
  return ids;
}

std::vector<const scenario::Vehicle*> pooled_vehicles(const scenario::Scenario& scenario,
                                                      std::span<const std::uint32_t> ids) {
  std::vector<const scenario::Vehicle*> out;
  for (const std::uint32_t id : ids) {
    const scenario::Vehicle* v = scenario.find_station(id);
    if (v == nullptr)
      throw ConfigError(fmt::format("--stations: {} is not a station of scenario {}", id,
                                    scenario.source.empty() ? scenario.name : scenario.source));
    if (v->station_kind != scenario::StationKind::kPooled)
      throw ConfigError(
          fmt::format("--stations: station {} (vehicle '{}') is not pooled in scenario {} (its "
                      "\"station\": {{\"kind\"}} is \"full\")",
                      id, v->id, scenario.source.empty() ? scenario.name : scenario.source));
    out.push_back(v);
  }
  return out;
}

Forwarding resolve_forwarding(std::string_view option, const std::string& why_not_kernel) {
  if (option == "user")
    return Forwarding::kUser;
  if (option == "kernel") {
    if (!why_not_kernel.empty())
      throw ConfigError("--forwarding kernel: the kernel bridge cannot carry this channel: " +
                        why_not_kernel);
    return Forwarding::kKernel;
  }
  if (option == "auto")
    return why_not_kernel.empty() ? Forwarding::kKernel : Forwarding::kUser;
  throw ConfigError(fmt::format("--forwarding '{}': expected auto, kernel or user", option));
}

std::filesystem::path station_pki_dir(const std::filesystem::path& pki_dir,
                                      std::uint32_t station_id) {
  const std::filesystem::path dir = pki_dir / std::to_string(station_id);
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec))
    throw ConfigError(fmt::format(
        "--pki-dir: no directory {} for station {} (its-pki export writes one per station)",
        dir.string(), station_id));
  return dir;
}

}  // namespace tb::host
