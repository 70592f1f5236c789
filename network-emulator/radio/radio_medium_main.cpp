// radio-medium: runs the stations' radios and the shared medium on their own, for tests and for
// launchers that do not run the whole network emulator. Usage in README.md ("Radios").

#include <unistd.h>

#include <charconv>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <optional>
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
#include "common/map/scenario_map.hpp"
#include "common/scenario/loader.hpp"
#include "common/trace/tracer.hpp"
#include "common/wire/vehicle_state.hpp"
#include "network-emulator/radio/channel.hpp"
#include "network-emulator/radio/frame_tag.hpp"
#include "network-emulator/radio/hwsim_radios.hpp"
#include "network-emulator/radio/medium.hpp"
#include "network-emulator/radio/packet_socket.hpp"
#include "network-emulator/radio/veth_radios.hpp"

namespace radio = tb::emu::radio;
namespace asio = boost::asio;

namespace {

constexpr int kExitUsage = 1;
constexpr int kExitSetup = 3;

struct Options {
  std::string scenario;
  std::string stations;
  std::string mode = "auto";
  std::string positions = "udp://0.0.0.0:4701";
  std::string prefix = radio::kDefaultPrefix;
  std::string ethertype = "0x8947";
  std::string stats_file;
  double stats_interval_s = 0.0;
  std::uint64_t seed = 1;
  std::string log_level = "info";
  std::string trace_file;
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
    if (const auto* v = sc.find_vehicle(key)) {
      s.id = v->station_id;
    } else {
      s.id = parse_u32(key, "--stations");
      if (!sc.find_station(s.id))
        throw UsageError("--stations: station " + key + " is not in scenario " + sc.source);
    }
    for (const auto& o : out)
      if (o.id == s.id)
        throw UsageError("--stations: station " + key + " given twice");
    out.push_back(std::move(s));
  }
  if (out.empty())
    throw UsageError("--stations: no station given");
  return out;
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

// Where each vehicle starts, so the channel has distances before the first state arrives.
void seed_positions(const tb::scenario::Scenario& sc, radio::PositionTable& table) {
  const tb::map::ScenarioMap map(sc);
  for (const auto& v : sc.vehicles) {
    const tb::map::Placement p = map.place(v.spawn);
    table.set(v.station_id, radio::StationPosition{{p.x, p.y, p.z}, -1});
  }
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

void write_stats(const std::string& file, const radio::Channel& channel) {
  if (file.empty())
    return;
  // Written beside and renamed, so that a reader never sees half a file.
  const std::string tmp = file + ".tmp";
  {
    std::ofstream out(tmp);
    out << channel.stats_json().dump(2) << '\n';
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
  const std::uint16_t ethertype = parse_ethertype(opt.ethertype);
  const auto positions_ep = parse_udp(opt.positions);
  if (opt.prefix.empty() || opt.prefix.size() > 5)
    throw UsageError("--prefix: \"" + opt.prefix +
                     "\" must have 1 to 5 characters (interface "
                     "names hold 15, the station id takes up to 10)");

  radio::PositionTable positions;
  seed_positions(sc, positions);
  radio::Channel channel(sc.channel, positions, opt.seed);
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

  const radio::MediumChoice choice = radio::choose_medium(opt.mode);
  spdlog::info("radio-medium: using {} ({})", radio::to_string(choice.kind), choice.why);

  asio::io_context io;
  tb::clock::AsioRuntime runtime(io);
  radio::Medium medium(runtime, channel);
  // One `medium.rx` record per frame a station puts on the air, when it comes in: the end of
  // t4 (stack → interface → medium) and, for a CAM, its sender and generationDeltaTime, by
  // which the report joins it to its.cam_tx and the receivers (docs/tracing.md).
  const auto frame_tracer = [](radio::LinkFraming framing) {
    return [framing](radio::StationId from, std::span<const std::uint8_t> frame) {
      auto& t = tb::trace::global();
      if (const auto cam = radio::peek_cam(frame, framing))
        t.record("medium.rx", {{"src", from},
                               {"station", cam->station_id},
                               {"gdt", unsigned{cam->generation_delta_time}},
                               {"bytes", frame.size()}});
      else
        t.record("medium.rx", {{"src", from}, {"bytes", frame.size()}});
    };
  };
  if (tb::trace::global().enabled())
    medium.set_frame_observer(frame_tracer(radio::LinkFraming::kEthernet));

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
  std::map<radio::StationId, std::unique_ptr<radio::VethPort>> ports;
  std::unique_ptr<radio::HwsimRadios> hwsim;
  std::unique_ptr<radio::HwsimMedium> hwsim_medium;
  try {
    if (choice.kind == radio::MediumKind::kVeth) {
      for (const auto& name : radio::VethRadios::remove_leftovers(opt.prefix))
        spdlog::warn("radio-medium: removed {} left by a run that did not end cleanly", name);
      veths = std::make_unique<radio::VethRadios>(stations, opt.prefix);
      for (const auto& s : stations) {
        auto& port = ports[s.id] = std::make_unique<radio::VethPort>(
            io, s.id, veths->host_ifname(s.id), ethertype, medium);
        medium.attach(s.id, *port);
      }
      for (auto& [id, p] : ports)
        p->start();
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
          medium.detach(id);
          ports.erase(id);
          try {
            veths->reattach(id);
            auto& port = ports[id] = std::make_unique<radio::VethPort>(
                io, id, veths->host_ifname(id), ethertype, medium);
            medium.attach(id, *port);
            port->start();
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
      write_stats(opt.stats_file, channel);
      arm_stats();
    });
  };
  arm_stats();

  spdlog::info("radio-medium: {} stations on the air, channel model {}, positions on {}",
               stations.size(), radio::to_string(sc.channel.kind), opt.positions);
  // Launchers and tests wait for this line before they send.
  std::printf("radio-medium: ready\n");
  std::fflush(stdout);

  io.run();
  write_stats(opt.stats_file, channel);
  tb::trace::global().flush();
  const auto t = channel.totals();
  const std::uint64_t frames_in = hwsim_medium ? hwsim_medium->frames_in() : medium.frames_in();
  spdlog::info("radio-medium: {} frames in, {} delivered, {} dropped", frames_in, t.delivered,
               t.dropped_total());
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
                 "/run/netns or a path such as /proc/PID/ns/net")
      ->required();
  app.add_option("--mode", opt.mode, "auto (hwsim when the kernel has it), hwsim or veth")
      ->check(CLI::IsMember({"auto", "hwsim", "veth"}));
  app.add_option("--positions", opt.positions, "where vehicle states arrive, udp://ADDR:PORT");
  app.add_option("--prefix", opt.prefix, "name prefix of host-side interfaces and radios");
  app.add_option("--ethertype", opt.ethertype, "veth medium: 0x8947 (GeoNetworking) or all");
  app.add_option("--stats", opt.stats_file, "write per-link statistics (JSON) here on exit");
  app.add_option("--stats-interval", opt.stats_interval_s, "and every this many seconds");
  app.add_option("--seed", opt.seed, "seed of the channel model's random numbers");
  app.add_option("--trace", opt.trace_file,
                 "write medium.frame trace records (JSON lines) to FILE; default "
                 "$TESTBED_TRACE_DIR/radio-medium.jsonl when that is set");
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
