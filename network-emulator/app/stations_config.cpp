#include "network-emulator/app/stations_config.hpp"

#include <fstream>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <boost/asio/ip/address.hpp>
#include <nlohmann/json.hpp>

namespace tb::emu {

namespace {

[[noreturn]] void fail(const std::string& file, const std::string& where, const std::string& why) {
  throw StationsConfigError(where.empty() ? fmt::format("{}: {}", file, why)
                                          : fmt::format("{}: {}: {}", file, where, why));
}

std::uint16_t port_field(const nlohmann::json& j, const char* key, std::uint16_t fallback,
                         const std::string& file, const std::string& where) {
  if (!j.contains(key))
    return fallback;
  const auto& v = j[key];
  if (!v.is_number_integer() || v.get<std::int64_t>() < 1 || v.get<std::int64_t>() > 65535)
    fail(file, where + "/" + key, fmt::format("{} is not a port number (1..65535)", v.dump()));
  return static_cast<std::uint16_t>(v.get<std::int64_t>());
}

std::string string_field(const nlohmann::json& j, const char* key, const std::string& fallback,
                         const std::string& file, const std::string& where) {
  if (!j.contains(key))
    return fallback;
  if (!j[key].is_string())
    fail(file, where + "/" + key, fmt::format("{} is not a string", j[key].dump()));
  return j[key].get<std::string>();
}

}  // namespace

std::vector<StationEndpoints> parse_stations(std::string_view json_text, const std::string& file,
                                             const scenario::Scenario& scenario) {
  nlohmann::json root;
  try {
    root = nlohmann::json::parse(json_text);
  } catch (const nlohmann::json::parse_error& e) {
    fail(file, "", fmt::format("not valid JSON: {}", e.what()));
  }
  if (!root.is_object() || !root.contains("stations") || !root["stations"].is_array())
    fail(file, "/stations", "expected an object with a \"stations\" array");
  static const std::set<std::string> kKeys{"station_id", "address",       "gnss_port",  "can_port",
                                           "netns",      "can_interface", "signal_port"};
  std::vector<StationEndpoints> out;
  std::set<std::uint32_t> seen;
  const auto& list = root["stations"];
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string where = fmt::format("/stations/{}", i);
    const auto& j = list[i];
    if (!j.is_object())
      fail(file, where, "expected an object");
    for (const auto& [key, value] : j.items())
      if (!kKeys.contains(key))
        fail(file, where + "/" + key, "unknown field");
    if (!j.contains("station_id") || !j["station_id"].is_number_unsigned() ||
        j["station_id"].get<std::uint64_t>() > 0xFFFFFFFFull)
      fail(file, where + "/station_id", "required, an integer 0..4294967295");
    StationEndpoints e;
    e.station_id = static_cast<std::uint32_t>(j["station_id"].get<std::uint64_t>());
    e.rsu = scenario.find_rsu(e.station_id) != nullptr;
    if (!e.rsu && !scenario.find_station(e.station_id))
      fail(file, where + "/station_id",
           fmt::format("station {} is not in scenario {}", e.station_id, scenario.source));
    for (const char* key : {"can_port", "can_interface"})
      if (e.rsu && j.contains(key))
        fail(file, where + "/" + key,
             fmt::format("station {} is an RSU, which has no CAN bus", e.station_id));
    if (!e.rsu && j.contains("signal_port"))
      fail(file, where + "/signal_port",
           fmt::format("station {} is a vehicle; only RSUs get the signal feed", e.station_id));
    if (!seen.insert(e.station_id).second)
      fail(file, where + "/station_id", fmt::format("station {} listed twice", e.station_id));
    e.address = string_field(j, "address", e.address, file, where);
    boost::system::error_code ec;
    boost::asio::ip::make_address(e.address, ec);
    if (ec)
      fail(file, where + "/address", fmt::format("\"{}\" is not an IP address", e.address));
    e.gnss_port = port_field(j, "gnss_port", e.gnss_port, file, where);
    e.can_port = port_field(j, "can_port", e.can_port, file, where);
    e.signal_port = port_field(j, "signal_port", e.signal_port, file, where);
    e.netns = string_field(j, "netns", e.netns, file, where);
    if (e.netns.find('/') != std::string::npos)
      fail(file, where + "/netns",
           fmt::format("\"{}\" is a path; give the name under /run/netns", e.netns));
    e.can_interface = string_field(j, "can_interface", e.can_interface, file, where);
    if (e.can_interface.empty() || e.can_interface.size() > 15)
      fail(file, where + "/can_interface",
           fmt::format("\"{}\" is not an interface name", e.can_interface));
    out.push_back(std::move(e));
  }
  return out;
}

std::vector<StationEndpoints> load_stations(const std::filesystem::path& file,
                                            const scenario::Scenario& scenario) {
  std::ifstream in(file);
  if (!in)
    throw StationsConfigError(fmt::format("{}: cannot open the stations file", file.string()));
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_stations(ss.str(), file.string(), scenario);
}

std::vector<StationEndpoints> default_stations(const scenario::Scenario& scenario) {
  std::vector<StationEndpoints> out;
  for (std::size_t i = 0; i < scenario.vehicles.size(); ++i) {
    StationEndpoints e;
    e.station_id = scenario.vehicles[i].station_id;
    e.gnss_port = static_cast<std::uint16_t>(kDefaultGnssPort + i);
    e.can_port = static_cast<std::uint16_t>(kDefaultCanPort + i);
    out.push_back(e);
  }
  for (std::size_t k = 0; k < scenario.rsus.size(); ++k) {
    const std::size_t i = scenario.vehicles.size() + k;
    StationEndpoints e;
    e.station_id = scenario.rsus[k].station_id;
    e.rsu = true;
    e.gnss_port = static_cast<std::uint16_t>(kDefaultGnssPort + i);
    e.can_port = 0;
    e.signal_port = static_cast<std::uint16_t>(wire::kRsuSignalPort + k);
    out.push_back(e);
  }
  return out;
}

}  // namespace tb::emu
