#include "network-emulator/radio/placement.hpp"

#include <charconv>
#include <fstream>
#include <map>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace tb::emu::radio {
namespace {

using nlohmann::json;

[[noreturn]] void fail(const std::string& source, const std::string& field,
                       const std::string& what) {
  throw PlacementError(fmt::format("placement {}: {}: {}", source, field, what));
}

std::string shown(const json& v) {
  std::string s = v.dump();
  if (s.size() > 60)
    s = s.substr(0, 57) + "...";
  return s;
}

std::vector<StationId> station_list(const json& node, const char* key, const std::string& field,
                                    const std::string& source) {
  std::vector<StationId> out;
  const auto it = node.find(key);
  if (it == node.end())
    return out;
  if (!it->is_array())
    fail(source, field, "must be an array of station ids, not " + shown(*it));
  for (std::size_t k = 0; k < it->size(); ++k) {
    const json& v = (*it)[k];
    if (!v.is_number_unsigned() || v.get<std::uint64_t>() > 0xFFFFFFFFu)
      fail(source, fmt::format("{}[{}]", field, k),
           shown(v) + " is not a station id (0 to 4294967295)");
    out.push_back(v.get<StationId>());
  }
  return out;
}

}  // namespace

const PlacementNode* Placement::find(const std::string& name) const {
  for (const auto& n : nodes)
    if (n.name == name)
      return &n;
  return nullptr;
}

const PlacementNode* Placement::node_of(StationId id) const {
  for (const auto& n : nodes) {
    for (const StationId s : n.stations)
      if (s == id)
        return &n;
    for (const StationId s : n.pooled)
      if (s == id)
        return &n;
  }
  return nullptr;
}

std::optional<HostPort> parse_host_port(const std::string& text) {
  const auto colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == text.size())
    return std::nullopt;
  std::string host = text.substr(0, colon);
  if (host.front() == '[') {
    if (host.size() < 3 || host.back() != ']')
      return std::nullopt;
    host = host.substr(1, host.size() - 2);
  } else if (host.find(':') != std::string::npos) {
    return std::nullopt;  // an IPv6 address needs its brackets
  }
  unsigned port = 0;
  const char* b = text.data() + colon + 1;
  const char* e = text.data() + text.size();
  const auto [p, ec] = std::from_chars(b, e, port);
  if (ec != std::errc{} || p != e || port == 0 || port > 65535)
    return std::nullopt;
  return HostPort{host, static_cast<std::uint16_t>(port)};
}

Placement parse_placement(const std::string& text, const std::string& source) {
  json j;
  try {
    j = json::parse(text);
  } catch (const json::parse_error& e) {
    fail(source, "(file)", std::string("not JSON: ") + e.what());
  }
  if (!j.is_object() || !j.contains("nodes"))
    fail(source, "nodes", "missing (the top level must be an object with \"nodes\")");
  const json& nodes = j["nodes"];
  if (!nodes.is_array() || nodes.empty())
    fail(source, "nodes", "must be a non-empty array, not " + shown(nodes));
  Placement out;
  out.source = source;
  std::map<StationId, std::string> owner;  // station → "node (field)"
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const json& n = nodes[i];
    const std::string at = fmt::format("nodes[{}]", i);
    if (!n.is_object())
      fail(source, at, "must be an object, not " + shown(n));
    PlacementNode node;
    const auto name = n.find("name");
    if (name == n.end() || !name->is_string() || name->get<std::string>().empty())
      fail(source, at + ".name",
           name == n.end() ? std::string("missing") : shown(*name) + " is not a node name");
    node.name = name->get<std::string>();
    if (out.find(node.name))
      fail(source, at + ".name", "node \"" + node.name + "\" appears twice");
    const auto medium = n.find("medium");
    if (medium == n.end())
      fail(source, at + ".medium", "missing (HOST:PORT of the node's radio-medium federation)");
    const auto hp = medium->is_string() ? parse_host_port(medium->get<std::string>())
                                        : std::optional<HostPort>{};
    if (!hp)
      fail(source, at + ".medium", shown(*medium) + " is not HOST:PORT (port 1 to 65535)");
    node.medium_host = hp->host;
    node.medium_port = hp->port;
    node.stations = station_list(n, "stations", at + ".stations", source);
    node.pooled = station_list(n, "pooled", at + ".pooled", source);
    if (const auto sh = n.find("station_hosts"); sh != n.end()) {
      if (!sh->is_number_unsigned() || sh->get<std::uint64_t>() > 1000)
        fail(source, at + ".station_hosts", shown(*sh) + " is not a count (0 to 1000)");
      node.station_hosts = sh->get<unsigned>();
    }
    if (!node.pooled.empty() && node.station_hosts == 0)
      fail(source, at + ".station_hosts",
           fmt::format("0, but the node has {} pooled stations to run", node.pooled.size()));
    for (const char* key : {"stations", "pooled"}) {
      const auto& list = std::string_view(key) == "stations" ? node.stations : node.pooled;
      for (const StationId id : list) {
        const std::string here = fmt::format("{} ({})", node.name, key);
        const auto [it, fresh] = owner.emplace(id, here);
        if (!fresh)
          fail(source, fmt::format("{}.{}", at, key),
               fmt::format("station {} is on {} and on {}: every station is on exactly one node",
                           id, it->second, here));
      }
    }
    out.nodes.push_back(std::move(node));
  }
  return out;
}

Placement load_placement(const std::string& path) {
  std::ifstream in(path);
  if (!in)
    throw PlacementError(fmt::format("placement {}: cannot be read", path));
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_placement(ss.str(), path);
}

}  // namespace tb::emu::radio
