// radio-medium: runs the stations' radios and the shared medium on their own, for tests and for
// launchers that do not run the whole network emulator. Usage in README.md ("Radios").

#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>
#include <nlohmann/json.hpp>

#include "common/clock/asio_runtime.hpp"
#include "common/map/rsu_site.hpp"
#include "common/map/scenario_map.hpp"
#include "common/scenario/loader.hpp"
#include "common/trace/tracer.hpp"
#include "common/util/realtime.hpp"
#include "common/wire/vehicle_state.hpp"
#include "network-emulator/radio/bridge_medium.hpp"
#include "network-emulator/radio/channel.hpp"
#include "network-emulator/radio/federation.hpp"
#include "network-emulator/radio/federation_socket.hpp"
#include "network-emulator/radio/frame_tag.hpp"
#include "network-emulator/radio/hwsim_radios.hpp"
#include "network-emulator/radio/medium.hpp"
#include "network-emulator/radio/placement.hpp"
#include "network-emulator/radio/veth_ports.hpp"
#include "network-emulator/radio/veth_radios.hpp"

namespace radio = tb::emu::radio;
namespace asio = boost::asio;

namespace {

constexpr int kExitUsage = 1;
constexpr int kExitSetup = 3;

struct Options {
  std::string scenario;
  std::string stations;
  std::vector<std::string> pooled;
  std::string mode = "auto";
  std::string forwarding = "auto";
  // 4702: the emulator hears the vehicle states on 4700 and the signal feed on 4701.
  std::string positions = "udp://0.0.0.0:4702";
  std::string prefix = radio::kDefaultPrefix;
  std::string ethertype = "0x8947";
  std::string stats_file;
  double stats_interval_s = 0.0;
  std::uint64_t seed = 1;
  std::string log_level = "info";
  std::string trace_file;
  std::string federation;  ///< placement file (issue 35)
  std::string node;
  std::string federation_listen = "0.0.0.0:4730";
  int realtime_priority = 0;
};

class UsageError : public std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::uint32_t parse_u32(std::string_view s, const std::string& what) {
  std::uint32_t v = 0;
  const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc{} || p != s.data() + s.size())
    throw UsageError(what + ": \"" + std::string(s) + "\" is not a number");
  return v;
}

// "1001=ns1,1002=/proc/42/ns/net,red=ns3": station ids or the scenario's vehicle ids.
radio::StationId scenario_station(const std::string& key, const tb::scenario::Scenario& sc,
                                  const std::string& option) {
  if (const auto* v = sc.find_vehicle(key))
    return v->station_id;
  for (const auto& r : sc.rsus)  // an RSU (issue 34) by its scenario id
    if (r.id == key)
      return r.station_id;
  const radio::StationId id = parse_u32(key, option);
  if (!sc.find_station(id) && !sc.find_rsu(id))
    throw UsageError(option + ": station " + key + " is not in scenario " + sc.source);
  return id;
}

std::vector<radio::StationSpec> parse_stations(const std::string& text,
                                               const tb::scenario::Scenario& sc) {
  std::vector<radio::StationSpec> out;
  std::string_view rest = text;
  while (!rest.empty()) {
    const auto comma = rest.find(',');
    const std::string_view item = rest.substr(0, comma);
    rest = comma == std::string_view::npos ? std::string_view{} : rest.substr(comma + 1);
    const auto eq = item.find('=');
    if (eq == std::string_view::npos || eq == 0 || eq + 1 == item.size())
      throw UsageError("--stations: \"" + std::string(item) + "\" is not ID=NETNS");
    const std::string key(item.substr(0, eq));
    radio::StationSpec s;
    s.netns = std::string(item.substr(eq + 1));
    s.id = scenario_station(key, sc, "--stations");
    for (const auto& o : out)
      if (o.id == s.id)
        throw UsageError("--stations: station " + key + " given twice");
    out.push_back(std::move(s));
  }
  return out;
}

// Each --pooled "NETNS=3004,3007,...": one station-host's namespace and its stations (station
// ids or the scenario's vehicle ids), none of them a full station or another host's.
std::vector<radio::PooledHostSpec> parse_pooled(const std::vector<std::string>& texts,
                                                const std::vector<radio::StationSpec>& full,
                                                const tb::scenario::Scenario& sc) {
  std::vector<radio::PooledHostSpec> out;
  std::set<radio::StationId> seen;
  for (const auto& f : full)
    seen.insert(f.id);
  for (const std::string& text : texts) {
    const auto eq = text.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
      throw UsageError("--pooled: \"" + text + "\" is not NETNS=ID[,ID...]");
    radio::PooledHostSpec h;
    h.netns = text.substr(0, eq);
    std::string_view rest = std::string_view(text).substr(eq + 1);
    while (!rest.empty()) {
      const auto comma = rest.find(',');
      const std::string key(rest.substr(0, comma));
      rest = comma == std::string_view::npos ? std::string_view{} : rest.substr(comma + 1);
      if (key.empty())
        throw UsageError("--pooled: \"" + text + "\" has an empty station id");
      const radio::StationId id = scenario_station(key, sc, "--pooled");
      const auto* vehicle = sc.find_station(id);  // null: an RSU, always a full station
      if (vehicle == nullptr || vehicle->station_kind != tb::scenario::StationKind::kPooled)
        throw UsageError("--pooled: station " + key + " is not \"pooled\" in scenario " +
                         sc.source + " (its vehicle's station.kind)");
      if (!seen.insert(id).second)
        throw UsageError("--pooled: station " + key +
                         " is given twice (in --stations or another --pooled)");
      h.stations.push_back(id);
    }
    if (h.stations.empty())
      throw UsageError("--pooled: \"" + text + "\" lists no station");
    out.push_back(std::move(h));
  }
  return out;
}

// --federation: this node's stations must be exactly its placement entry, and every station of
// the scenario must be on some node, so that no frame is federated to the wrong node or lost.
void check_placement(const radio::Placement& p, const std::string& node,
                     const std::vector<radio::StationSpec>& stations,
                     const std::vector<radio::PooledHostSpec>& hosts,
                     const tb::scenario::Scenario& sc) {
  const radio::PlacementNode* self = p.find(node);
  if (!self)
    throw UsageError("--node " + node + ": placement " + p.source + " has no node of that name");
  std::set<radio::StationId> full, pooled;
  for (const auto& s : stations)
    full.insert(s.id);
  for (const auto& h : hosts)
    pooled.insert(h.stations.begin(), h.stations.end());
  const auto compare = [&](const std::set<radio::StationId>& given,
                           const std::vector<radio::StationId>& placed, const char* option,
                           const char* field) {
    for (const auto id : given)
      if (std::find(placed.begin(), placed.end(), id) == placed.end()) {
        const auto* owner = p.node_of(id);
        throw UsageError(
            fmt::format("{}: station {} is not in node {}'s \"{}\" in placement {} ({})", option,
                        id, node, field, p.source,
                        owner ? "it is on node " + owner->name : std::string("no node has it")));
      }
    for (const auto id : placed)
      if (!given.contains(id))
        throw UsageError(fmt::format("{}: station {} of node {} (placement {}, \"{}\") is missing",
                                     option, id, node, p.source, field));
  };
  compare(full, self->stations, "--stations", "stations");
  compare(pooled, self->pooled, "--pooled", "pooled");
  for (const auto& n : p.nodes)
    for (const auto* list : {&n.stations, &n.pooled})
      for (const auto id : *list)
        if (!sc.find_station(id) && !sc.find_rsu(id))
          throw UsageError(fmt::format("placement {}: station {} (node {}) is not in scenario {}",
                                       p.source, id, n.name, sc.source));
  for (const auto& v : sc.vehicles)
    if (!p.node_of(v.station_id))
      throw UsageError(fmt::format("placement {}: station {} (vehicle {}) is on no node", p.source,
                                   v.station_id, v.id));
  for (const auto& r : sc.rsus)
    if (!p.node_of(r.station_id))
      throw UsageError(fmt::format("placement {}: station {} (RSU {}) is on no node", p.source,
                                   r.station_id, r.id));
}

std::uint16_t parse_ethertype(const std::string& s) {
  if (s == "all")
    return radio::kEthertypeAll;
  std::string_view v = s;
  if (v.starts_with("0x"))
    v.remove_prefix(2);
  std::uint32_t e = 0;
  const auto [p, ec] = std::from_chars(v.data(), v.data() + v.size(), e, 16);
  if (ec != std::errc{} || p != v.data() + v.size() || e < 0x0600 || e > 0xffff)
    throw UsageError("--ethertype: \"" + s +
                     "\" is neither \"all\" nor an ethertype such as 0x8947");
  return static_cast<std::uint16_t>(e);
}

asio::ip::udp::endpoint parse_udp(const std::string& url) {
  constexpr std::string_view scheme = "udp://";
  if (!url.starts_with(scheme))
    throw UsageError("--positions: \"" + url + "\" does not start with udp://");
  const std::string hostport = url.substr(scheme.size());
  const auto colon = hostport.rfind(':');
  if (colon == std::string::npos)
    throw UsageError("--positions: \"" + url + "\" has no port");
  boost::system::error_code ec;
  const auto addr = asio::ip::make_address(hostport.substr(0, colon), ec);
  if (ec)
    throw UsageError("--positions: \"" + hostport.substr(0, colon) + "\" is not an IP address");
  const auto port = parse_u32(hostport.substr(colon + 1), "--positions port");
  if (port > 65535)
    throw UsageError("--positions: port " + std::to_string(port) + " out of range");
  return {addr, static_cast<unsigned short>(port)};
}

// Where each vehicle starts, so the channel has distances before the first state arrives; and
// where each RSU's antenna stands for good (no state ever moves it: the stream has none).
void seed_positions(const tb::scenario::Scenario& sc, radio::PositionTable& table) {
  const tb::map::ScenarioMap map(sc);
  for (const auto& v : sc.vehicles) {
    const tb::map::Placement p = map.place(v.spawn);
    table.set(v.station_id, radio::StationPosition{{p.x, p.y, p.z}, -1});
  }
  const auto sites = tb::map::rsu_sites(sc.rsus, map);
  for (std::size_t k = 0; k < sites.size(); ++k)
    table.set(sc.rsus[k].station_id,
              radio::StationPosition{{sites[k].x, sites[k].y, sites[k].antenna_z}, -1});
}

// Vehicle states (common/wire) on UDP keep the position table current.
class PositionListener {
 public:
  PositionListener(asio::io_context& io, const asio::ip::udp::endpoint& ep,
                   radio::PositionTable& table)
      : socket_(io, ep), table_(table) {
    receive();
  }
  void receive() {
    socket_.async_receive_from(asio::buffer(buf_), from_,
                               [this](const boost::system::error_code& ec, std::size_t n) {
                                 if (ec == asio::error::operation_aborted)
                                   return;
                                 if (!ec)
                                   handle(n);
                                 receive();
                               });
  }

 private:
  void handle(std::size_t n) {
    // Batch datagrams (docs/wire.md), as the sim-clients send them and the emulator forwards.
    auto count = tb::wire::decode_batch(std::span<const std::uint8_t>(buf_.data(), n), states_);
    if (!count) {
      if (bad_++ == 0)
        spdlog::warn(
            "radio-medium: bad vehicle-state datagram from {}: {} ({} bytes; counted, said once)",
            from_.address().to_string(), tb::wire::to_string(count.error()), n);
      return;
    }
    for (const auto& s : states_)
      table_.update(s);
  }
  std::vector<tb::wire::VehicleState> states_;
  asio::ip::udp::socket socket_;
  asio::ip::udp::endpoint from_;
  std::array<std::uint8_t, 2048> buf_{};
  radio::PositionTable& table_;
  std::uint64_t bad_ = 0;
};

/// How the frames move between the stations' radios, for the statistics file.
struct Forwarding {
  radio::BridgeMedium* bridge = nullptr;  ///< in the kernel; else in this program (or hwsim)
  radio::VethPorts* ports = nullptr;      ///< in this program, veth
  const radio::Federation* federation = nullptr;
};

void write_stats(const std::string& file, const radio::Channel& channel, const Forwarding& fw) {
  if (file.empty())
    return;
  nlohmann::json j = channel.stats_json();
  if (fw.bridge) {
    // The kernel forwarded; the channel counted what it decided. A port whose station's queue
    // was full dropped frames the counts above call delivered: said here, per receiver.
    j["forwarding"] = "kernel";
    nlohmann::json drops = nlohmann::json::object();
    for (const auto& [id, n] : fw.bridge->kernel_drops())
      drops[std::to_string(id)] = n;
    j["kernel_dropped"] = drops;
    j["tap_missed"] = fw.bridge->tap_drops();
    j["unknown_sender"] = fw.bridge->unknown_sender();
  } else {
    j["forwarding"] = "radio-medium";
    if (fw.ports)
      j["unknown_sender"] = fw.ports->unknown_sender();
  }
  if (const auto* f = fw.federation) {
    nlohmann::json peers = nlohmann::json::object();
    for (std::size_t k = 0; k < f->peers().size(); ++k)
      peers[f->peers()[k].name] = f->peer_up(k) ? "up" : "down";
    j["federation"] = {{"node", f->self()},
                       {"frames_out", f->frames_out()},
                       {"datagrams_out", f->datagrams_out()},
                       {"peers_skipped", f->peers_skipped()},
                       {"frames_in", f->frames_in()},
                       {"rejected", f->rejected()},
                       {"peers", peers}};
  }
  // Written beside and renamed, so that a reader never sees half a file.
  const std::string tmp = file + ".tmp";
  {
    std::ofstream out(tmp);
    out << j.dump(2) << '\n';
    if (!out) {
      spdlog::error("radio-medium: cannot write statistics to {}", tmp);
      return;
    }
  }
  if (std::rename(tmp.c_str(), file.c_str()) != 0)
    spdlog::error("radio-medium: cannot rename {} to {}", tmp, file);
}

int run(const Options& opt) {
  tb::scenario::Scenario sc;
  try {
    sc = tb::scenario::load_file(opt.scenario);
  } catch (const tb::scenario::ScenarioError& e) {
    spdlog::error("{}", e.what());
    return tb::scenario::kExitBadScenario;
  }
  const auto stations = parse_stations(opt.stations, sc);
  const auto hosts = parse_pooled(opt.pooled, stations, sc);
  if (stations.empty() && hosts.empty())
    throw UsageError("--stations: no station given (and no --pooled host)");
  const std::uint16_t ethertype = parse_ethertype(opt.ethertype);
  const auto why_not_kernel = radio::why_bridge_cannot_carry(sc.channel);
  if (opt.forwarding == "kernel" && why_not_kernel)
    throw UsageError("--forwarding kernel: the kernel bridge cannot carry this channel: " +
                     *why_not_kernel);
  const auto positions_ep = parse_udp(opt.positions);
  std::optional<radio::Placement> placement;
  asio::ip::udp::endpoint federation_ep;
  if (!opt.federation.empty() || !opt.node.empty()) {
    if (opt.federation.empty() || opt.node.empty())
      throw UsageError("--federation and --node go together");
    try {
      // The placement itself may be given instead of its file (the container's
      // TESTBED_PLACEMENT may hold either).
      placement = opt.federation.starts_with("{")
                      ? radio::parse_placement(opt.federation, "(--federation, inline JSON)")
                      : radio::load_placement(opt.federation);
    } catch (const radio::PlacementError& e) {
      throw UsageError(e.what());
    }
    check_placement(*placement, opt.node, stations, hosts, sc);
    const auto hp = radio::parse_host_port(opt.federation_listen);
    boost::system::error_code ec;
    const auto addr = hp ? asio::ip::make_address(hp->host, ec) : asio::ip::address{};
    if (!hp || ec)
      throw UsageError("--federation-listen: \"" + opt.federation_listen +
                       "\" is not ADDRESS:PORT (an IP address, e.g. 0.0.0.0:4730)");
    federation_ep = {addr, hp->port};
    if (opt.mode == "hwsim")
      throw UsageError(
          "--mode hwsim with --federation: frames from other nodes are injected into the "
          "stations' veth radios; use --mode veth or auto");
  }
  if (opt.prefix.empty() || opt.prefix.size() > 5)
    throw UsageError("--prefix: \"" + opt.prefix +
                     "\" must have 1 to 5 characters (interface "
                     "names hold 15, the station id takes up to 10)");

  radio::PositionTable positions;
  seed_positions(sc, positions);
  radio::Channel channel(sc.channel, positions, opt.seed);
  // Range culling: cells one maximum range wide, so that a frame's possible receivers are in
  // the 3×3 cells around its sender (none for the ideal channel: everyone hears).
  if (const auto& r = channel.max_range_m())
    positions.index_cells(*r);
  // One `medium.frame` record per frame and possible receiver (docs/tracing.md): ok says
  // whether it was delivered; delayed frames carry the delay they were given.
  const std::string trace_path =
      opt.trace_file.empty() ? tb::trace::configure_from_env("radio-medium") : opt.trace_file;
  if (!opt.trace_file.empty())
    tb::trace::configure(opt.trace_file, "radio-medium");
  if (tb::trace::global().enabled()) {
    spdlog::info("radio-medium: trace records to {}", trace_path);
    channel.set_observer([](radio::StationId from, radio::StationId to, const radio::Decision& d) {
      auto& t = tb::trace::global();
      if (d.deliver)
        t.record("medium.frame", {{"src", from},
                                  {"dst", to},
                                  {"ok", true},
                                  {"delay_ns", static_cast<std::int64_t>(d.delay.count())}});
      else
        t.record(
            "medium.frame",
            {{"src", from}, {"dst", to}, {"ok", false}, {"reason", radio::to_string(d.reason)}});
    });
  }

  if (!hosts.empty() && opt.mode == "hwsim")
    throw UsageError(
        "--mode hwsim with --pooled: a station-host's stations share one interface, and one "
        "hwsim radio per pooled station (hundreds) is not what a host can own; use --mode "
        "veth or auto");
  radio::MediumChoice choice = radio::choose_medium(opt.mode);
  if (placement && choice.kind == radio::MediumKind::kHwsim) {
    choice = {radio::MediumKind::kVeth,
              "--federation injects other nodes' frames into veth radios, so the veth stand-in "
              "is used although the kernel has mac80211_hwsim"};
  }
  if (!hosts.empty() && choice.kind == radio::MediumKind::kHwsim) {
    choice = {radio::MediumKind::kVeth,
              "--pooled station-hosts join through one veth each, so the veth stand-in is used "
              "although the kernel has mac80211_hwsim"};
  }
  spdlog::info("radio-medium: using {} ({})", radio::to_string(choice.kind), choice.why);

  asio::io_context io;
  tb::clock::AsioRuntime runtime(io);
  radio::Medium medium(runtime, channel);
  // One `medium.rx` record per frame a station puts on the air, when it comes in: the end of
  // t4 (stack → interface → medium) and, for a CAM, its sender and generationDeltaTime, by
  // which the report joins it to its.cam_tx and the receivers (docs/tracing.md).
  // Stamped with the kernel's receive time where the medium has it: frames the kernel forwards
  // are read in blocks, well after they arrived.
  const auto frame_tracer = [](radio::LinkFraming framing) {
    return [framing](radio::StationId from, std::span<const std::uint8_t> frame,
                     std::int64_t unix_ns) {
      auto& t = tb::trace::global();
      if (unix_ns == 0)
        unix_ns = tb::trace::Tracer::now_ns();
      if (const auto cam = radio::peek_cam(frame, framing))
        t.record_at(unix_ns, "medium.rx",
                    {{"src", from},
                     {"station", cam->station_id},
                     {"gdt", unsigned{cam->generation_delta_time}},
                     {"bytes", frame.size()}});
      else
        t.record_at(unix_ns, "medium.rx", {{"src", from}, {"bytes", frame.size()}});
    };
  };
  // Federation (issue 35): bound before any radio exists, as the positions below. The Federation
  // itself is made once the forwarding is known (it delivers into the bridge or the medium).
  std::unique_ptr<radio::Federation> federation;
  std::unique_ptr<radio::FederationSocket> federation_socket;
  std::unique_ptr<radio::MediumRemoteSink> medium_sink;
  if (placement) {
    std::vector<radio::PlacementNode> peers;
    for (const auto& n : placement->nodes)
      if (n.name != opt.node)
        peers.push_back(n);
    try {
      federation_socket = std::make_unique<radio::FederationSocket>(
          io, federation_ep, peers,
          [&federation](std::span<const std::uint8_t> d, std::int64_t rx_ns,
                        std::int64_t kernel_rx_ns) {
            if (federation)
              federation->on_datagram(d, rx_ns, kernel_rx_ns);
          },
          [&federation](std::size_t peer, const std::string& why) {
            if (federation)
              federation->on_send_error(peer, why);
          });
    } catch (const boost::system::system_error& e) {
      spdlog::error("radio-medium: --federation-listen {}: cannot listen: {}",
                    opt.federation_listen, e.code().message());
      return kExitSetup;
    }
  }
  const auto local_frames =
      [&federation, tracer = tb::trace::global().enabled()
                                 ? radio::FrameObserver(frame_tracer(radio::LinkFraming::kEthernet))
                                 : radio::FrameObserver()](
          radio::StationId from, std::span<const std::uint8_t> frame, std::int64_t unix_ns) {
        if (tracer)
          tracer(from, frame, unix_ns);
        if (federation)
          federation->on_local_frame(from, frame, unix_ns);
      };
  if (tb::trace::global().enabled() || placement)
    medium.set_frame_observer(local_frames);

  // Bound before any radio exists, so that a busy port costs nothing to clean up.
  std::unique_ptr<PositionListener> listener;
  try {
    listener = std::make_unique<PositionListener>(io, positions_ep, positions);
  } catch (const boost::system::system_error& e) {
    spdlog::error("radio-medium: --positions {}: cannot listen: {}", opt.positions,
                  e.code().message());
    return kExitSetup;
  }

  std::unique_ptr<radio::VethRadios> veths;
  std::unique_ptr<radio::VethPorts> ports;      // forwarding in this program
  std::unique_ptr<radio::BridgeMedium> bridge;  // forwarding in the kernel
  std::unique_ptr<radio::HwsimRadios> hwsim;
  std::unique_ptr<radio::HwsimMedium> hwsim_medium;
  try {
    if (choice.kind == radio::MediumKind::kVeth) {
      for (const auto& name : radio::VethRadios::remove_leftovers(opt.prefix))
        spdlog::warn("radio-medium: removed {} left by a run that did not end cleanly", name);
      veths = std::make_unique<radio::VethRadios>(stations, opt.prefix, hosts);
      if (opt.forwarding == "kernel" || (opt.forwarding == "auto" && !why_not_kernel)) {
        bridge = std::make_unique<radio::BridgeMedium>(io, opt.prefix + "br", radio::owner_alias(),
                                                       ethertype, channel);
        for (const auto& s : stations)
          bridge->attach(s.id, veths->host_ifname(s.id));
        for (std::size_t k = 0; k < hosts.size(); ++k)
          bridge->attach_pooled_host(veths->pooled_host_ifname(k), hosts[k].stations);
        if (tb::trace::global().enabled())
          bridge->set_frame_observer(frame_tracer(radio::LinkFraming::kEthernet));
        if (placement)
          bridge->federate([&federation](radio::StationId from, std::span<const std::uint8_t> frame,
                                         std::int64_t unix_ns) {
            if (federation)
              federation->on_local_frame(from, frame, unix_ns);
          });
        bridge->start();
        spdlog::info(
            "radio-medium: forwarding in the kernel (bridge {}, every frame to every other "
            "station), since the channel is ideal without delay or jitter",
            bridge->bridge_name());
      } else {
        ports = std::make_unique<radio::VethPorts>(io, ethertype, medium);
        for (const auto& s : stations)
          ports->attach(s.id, veths->host_ifname(s.id));
        for (std::size_t k = 0; k < hosts.size(); ++k)
          ports->attach_pooled_host(veths->pooled_host_ifname(k), hosts[k].stations,
                                    radio::kPooledHostMtu);
        ports->start();
        spdlog::info("radio-medium: forwarding in radio-medium: {}",
                     why_not_kernel ? *why_not_kernel : std::string("--forwarding user"));
      }
    } else {
      for (const auto& name : radio::HwsimRadios::remove_leftovers(opt.prefix))
        spdlog::warn("radio-medium: removed radio {} left by a run that did not end cleanly", name);
      hwsim = std::make_unique<radio::HwsimRadios>(stations, opt.prefix);
      hwsim_medium = std::make_unique<radio::HwsimMedium>(io, runtime, channel, *hwsim);
      if (tb::trace::global().enabled())
        hwsim_medium->set_frame_observer(frame_tracer(radio::LinkFraming::kIeee80211));
      hwsim_medium->start();
    }
  } catch (const std::exception& e) {
    spdlog::error("radio-medium: {}", e.what());
    return kExitSetup;
  }

  asio::steady_timer heartbeat(io);
  std::function<void()> arm_heartbeat;
  if (placement) {
    radio::RemoteFrameSink* sink = bridge.get();
    if (!sink) {
      medium_sink = std::make_unique<radio::MediumRemoteSink>(medium);
      sink = medium_sink.get();
    }
    federation = std::make_unique<radio::Federation>(*placement, opt.node, channel, positions,
                                                     runtime, *federation_socket, *sink);
    federation->set_peer_events([](const radio::PeerEvent& e) {
      if (e.up)
        spdlog::info("radio-medium: peer node {} is up ({})", e.node, e.why);
      else
        spdlog::warn(
            "radio-medium: peer node {} is down: {}; its stations are not heard here "
            "until it is back",
            e.node, e.why);
    });
    federation->set_reject_observer([](std::string_view why) {
      static std::uint64_t n = 0;
      if (n++ == 0)
        spdlog::warn(
            "radio-medium: federation: datagram refused: {} (counted as rejected in the "
            "statistics; said once)",
            why);
    });
    if (tb::trace::global().enabled())
      federation->set_hop_observer(
          [](const radio::FederationDatagram& d, std::int64_t rx_ns, std::int64_t kernel_rx_ns) {
            auto& t = tb::trace::global();
            if (const auto cam = radio::peek_cam(d.frame, radio::LinkFraming::kEthernet))
              t.record_at(rx_ns, "medium.hop",
                          {{"src", d.sender},
                           {"node", d.node},
                           {"station", cam->station_id},
                           {"gdt", unsigned{cam->generation_delta_time}},
                           {"tx_ns", d.tx_unix_ns},
                           {"kernel_rx_ns", kernel_rx_ns},
                           {"bytes", d.frame.size()}});
            else
              t.record_at(rx_ns, "medium.hop",
                          {{"src", d.sender},
                           {"node", d.node},
                           {"tx_ns", d.tx_unix_ns},
                           {"kernel_rx_ns", kernel_rx_ns},
                           {"bytes", d.frame.size()}});
          });
    federation_socket->start();
    arm_heartbeat = [&] {
      heartbeat.expires_after(radio::Federation::kHeartbeatInterval);
      heartbeat.async_wait([&](const boost::system::error_code& ec) {
        if (ec)
          return;
        federation->tick();
        arm_heartbeat();
      });
    };
    federation->tick();
    arm_heartbeat();
    std::string names;
    for (const auto& p : federation->peers())
      names += fmt::format("{}{} ({}:{})", names.empty() ? "" : ", ", p.name, p.medium_host,
                           p.medium_port);
    spdlog::info("radio-medium: node {} of placement {}, federated with {} on {}", opt.node,
                 placement->source, names.empty() ? std::string("no other node") : names,
                 opt.federation_listen);
  }

  asio::signal_set signals(io, SIGINT, SIGTERM);
  signals.async_wait([&](const boost::system::error_code& ec, int sig) {
    if (!ec)
      spdlog::info("radio-medium: signal {}, cleaning up", sig);
    io.stop();
  });

  // SIGHUP: a station's namespace name now leads elsewhere (its container restarted and was
  // handed over again): give it a new radio there, leaving every other station's alone.
  asio::signal_set hangups(io, SIGHUP);
  std::function<void()> arm_hangup = [&] {
    hangups.async_wait([&](const boost::system::error_code& ec, int) {
      if (ec)
        return;
      if (!veths) {
        spdlog::warn(
            "radio-medium: SIGHUP: moving a radio to a new namespace needs the veth radios; "
            "restart radio-medium to move hwsim radios");
      } else {
        for (const auto id : veths->moved_stations()) {
          if (bridge)
            bridge->detach(id);
          else
            ports->detach(id);
          try {
            veths->reattach(id);
            if (bridge)
              bridge->attach(id, veths->host_ifname(id));
            else
              ports->attach(id, veths->host_ifname(id));
            spdlog::info("radio-medium: station {}: new namespace, wlan0 made again", id);
          } catch (const std::exception& e) {
            spdlog::error("radio-medium: station {}: no radio: {}", id, e.what());
          }
        }
      }
      arm_hangup();
    });
  };
  arm_hangup();

  asio::steady_timer stats_timer(io);
  std::function<void()> arm_stats = [&] {
    if (opt.stats_interval_s <= 0.0 || opt.stats_file.empty())
      return;
    stats_timer.expires_after(std::chrono::duration_cast<std::chrono::nanoseconds>(
        std::chrono::duration<double>(opt.stats_interval_s)));
    stats_timer.async_wait([&](const boost::system::error_code& ec) {
      if (ec)
        return;
      write_stats(opt.stats_file, channel, {bridge.get(), ports.get(), federation.get()});
      arm_stats();
    });
  };
  arm_stats();

  std::size_t pooled_count = 0;
  for (const auto& h : hosts)
    pooled_count += h.stations.size();
  spdlog::info(
      "radio-medium: {} stations on the air ({} pooled behind {} station-hosts), channel model "
      "{}{}, positions on {}",
      stations.size() + pooled_count, pooled_count, hosts.size(), radio::to_string(sc.channel.kind),
      channel.max_range_m()
          ? fmt::format(" (frames offered within {:.0f} m)", *channel.max_range_m())
          : std::string(),
      opt.positions);
  if (opt.realtime_priority != 0) {
    // Last, so that setting up the radios does not run at it: what is latency-critical is the
    // wake-up for a frame (docs/scale-out.md, "The hop between media").
    if (const auto r = tb::run_at_realtime_priority(opt.realtime_priority))
      spdlog::info("radio-medium: real-time scheduling: {} priority {}", r->policy, r->priority);
    else
      spdlog::warn(
          "radio-medium: --realtime-priority: cannot run at real-time priority: {}; running at "
          "normal priority (frames wait longer for this process to be scheduled)",
          r.error());
  }
  // Launchers and tests wait for this line before they send.
  std::printf("radio-medium: ready\n");
  std::fflush(stdout);

  io.run();
  if (bridge)
    bridge->drain_all();  // what the tap holds yet
  write_stats(opt.stats_file, channel, {bridge.get(), ports.get(), federation.get()});
  tb::trace::global().flush();
  const auto t = channel.totals();
  const std::uint64_t frames_in = hwsim_medium ? hwsim_medium->frames_in()
                                  : bridge     ? bridge->frames_in()
                                               : medium.frames_in();
  spdlog::info("radio-medium: {} frames in, {} delivered, {} dropped", frames_in, t.delivered,
               t.dropped_total());
  if (bridge) {
    std::uint64_t kernel_dropped = 0;
    for (const auto& [id, n] : bridge->kernel_drops())
      kernel_dropped += n;
    spdlog::info(
        "radio-medium: in the kernel: {} deliveries dropped (a station's queue full); "
        "{} frames not seen by the tap (its ring full: forwarded, but neither traced "
        "nor counted)",
        kernel_dropped, bridge->tap_drops());
  } else if (ports) {
    spdlog::info(
        "radio-medium: {} frames sent in {} sendmmsg calls ({} of them pooled deliveries), {} "
        "failed; {} frames from an unknown sender; {} receivers culled (out of range)",
        ports->sent(), ports->send_calls(), ports->pooled_frames_sent(), ports->send_errors(),
        ports->unknown_sender(), medium.culled());
  }
  if (federation)
    spdlog::info(
        "radio-medium: federation: {} local frames to {} peer datagrams ({} peers skipped, no "
        "station in range), {} frames from peers, {} datagrams refused",
        federation->frames_out(), federation->datagrams_out(), federation->peers_skipped(),
        federation->frames_in(), federation->rejected());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options opt;
  CLI::App app{
      "radio-medium: 802.11p radios for ITS stations in network namespaces, and the "
      "channel model between them"};
  app.add_option("--scenario", opt.scenario, "scenario file (channel model, stations)")->required();
  app.add_option("--stations", opt.stations,
                 "ID=NETNS,...: station id (or vehicle id) and its namespace, a name under "
                 "/run/netns or a path such as /proc/PID/ns/net");
  app.add_option("--pooled", opt.pooled,
                 "NETNS=ID[,ID...], repeatable: a station-host's namespace (one veth pair, "
                 "PREFIXh<k> here, wlan0 there) and its pooled stations");
  app.add_option("--mode", opt.mode, "auto (hwsim when the kernel has it), hwsim or veth")
      ->check(CLI::IsMember({"auto", "hwsim", "veth"}));
  app.add_option("--positions", opt.positions, "where vehicle states arrive, udp://ADDR:PORT");
  app.add_option("--prefix", opt.prefix, "name prefix of host-side interfaces and radios");
  app.add_option("--ethertype", opt.ethertype, "veth medium: 0x8947 (GeoNetworking) or all");
  app.add_option("--forwarding", opt.forwarding,
                 "veth medium: auto (in the kernel when the channel is ideal without delay or "
                 "jitter), kernel, or user (in this program, for any channel)")
      ->check(CLI::IsMember({"auto", "kernel", "user"}));
  app.add_option("--stats", opt.stats_file, "write per-link statistics (JSON) here on exit");
  app.add_option("--stats-interval", opt.stats_interval_s, "and every this many seconds");
  app.add_option("--seed", opt.seed, "seed of the channel model's random numbers");
  app.add_option("--trace", opt.trace_file,
                 "write medium.frame trace records (JSON lines) to FILE; default "
                 "$TESTBED_TRACE_DIR/radio-medium.jsonl when that is set");
  app.add_option("--federation", opt.federation,
                 "placement file (JSON), or the JSON itself: join this node's medium to the "
                 "other nodes' media "
                 "(issue 35, README.md \"Federated medium\")");
  app.add_option("--node", opt.node, "this node's name in the placement file");
  app.add_option("--federation-listen", opt.federation_listen,
                 "ADDRESS:PORT (UDP) where the other nodes' media send their frames");
  app.add_option("--realtime-priority", opt.realtime_priority,
                 "run the medium's thread under SCHED_FIFO at this priority (1..99; 0: normal "
                 "scheduling); refused by the kernel: a warning, and it runs at normal priority")
      ->check(CLI::Range(0, 99));
  app.add_option("--log-level", opt.log_level, "trace, debug, info, warn, error")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error"}));
  CLI11_PARSE(app, argc, argv);
  spdlog::set_level(spdlog::level::from_str(opt.log_level));
  try {
    return run(opt);
  } catch (const UsageError& e) {
    spdlog::error("radio-medium: {}", e.what());
    return kExitUsage;
  } catch (const std::exception& e) {
    spdlog::error("radio-medium: {}", e.what());
    return kExitSetup;
  }
}
