// network-emulator: the vehicles' hardware. Receives vehicle states from sim-clients and feeds
// every station's gpsd (NMEA over UDP) and CAN bus (SocketCAN vcan, or cannelloni over UDP).

#include <sys/resource.h>
#include <sys/socket.h>

#include <array>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <memory>
#include <string>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>

#include "common/can/netns.hpp"
#include "common/can/socketcan_bus.hpp"
#include "common/clock/asio_runtime.hpp"
#include "common/scenario/loader.hpp"
#include "common/trace/tracer.hpp"
#include "common/util/realtime.hpp"
#include "common/wire/signal_feed.hpp"
#include "network-emulator/app/batch_io.hpp"
#include "network-emulator/app/emulator.hpp"
#include "network-emulator/app/relay.hpp"
#include "network-emulator/app/stations_config.hpp"

namespace {

namespace asio = boost::asio;
using udp = asio::ip::udp;
using namespace tb;

constexpr int kExitFailure = 1;

/// A CAN bus that could not be opened: every send reports why, so the station is paused and
/// logged like one whose receiver went away.
class BrokenCanBus final : public can::CanBus {
 public:
  explicit BrokenCanBus(std::error_code ec) : ec_(ec) {}
  std::string_view kind() const override { return "broken"; }
  std::error_code send(std::span<const can::CanFrame>) override { return ec_; }
  void start_receive(FrameHandler) override {}

 private:
  std::error_code ec_;
};

/// The same for an NMEA feed.
class BrokenSink final : public emu::DatagramSink {
 public:
  explicit BrokenSink(std::error_code ec) : ec_(ec) {}
  std::error_code send(std::span<const std::uint8_t>) override { return ec_; }

 private:
  std::error_code ec_;
};

std::optional<udp::endpoint> parse_endpoint(const std::string& text) {
  const auto colon = text.rfind(':');
  if (colon == std::string::npos)
    return std::nullopt;
  boost::system::error_code ec;
  auto addr = asio::ip::make_address(text.substr(0, colon), ec);
  if (ec)
    return std::nullopt;
  try {
    const int port = std::stoi(text.substr(colon + 1));
    if (port < 0 || port > 65535)
      return std::nullopt;
    return udp::endpoint(addr, static_cast<unsigned short>(port));
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

/// A CAN_RAW socket per station with SocketCAN: lift the soft descriptor limit to the hard one.
void raise_fd_limit() {
  rlimit r{};
  if (::getrlimit(RLIMIT_NOFILE, &r) == 0 && r.rlim_cur < r.rlim_max) {
    r.rlim_cur = r.rlim_max;
    ::setrlimit(RLIMIT_NOFILE, &r);
  }
}

/// The UDP receiver of vehicle states: one async wait, then drains the socket without blocking.
/// What the states make (NMEA, CAN, forwarded states) is queued on the batch senders during a
/// receive batch and sent with one sendmmsg per socket at its end.
class StateReceiver {
 public:
  StateReceiver(asio::io_context& io, const udp::endpoint& listen, emu::Emulator& emulator,
                emu::BatchSenders& senders, const std::vector<udp::endpoint>& forward,
                emu::Relay* relay)
      : socket_(io), emulator_(emulator), senders_(senders), relay_(relay) {
    if (!forward.empty()) {
      forward_sender_ = &senders_.get("", AF_INET);
      for (const auto& to : forward)
        forward_sinks_.push_back(forward_sender_->add_sink(
            emu::Destination::from(to.data(), static_cast<socklen_t>(to.size()))));
    }
    socket_.open(listen.protocol());
    socket_.set_option(udp::socket::reuse_address(true));
    // 1000 vehicles at 100 Hz are 100k datagrams/s: a deep buffer rides out scheduling gaps.
    // SO_RCVBUFFORCE passes net.core.rmem_max where we may (CAP_NET_ADMIN); else best effort.
    const int size = 8 << 20;
    if (::setsockopt(socket_.native_handle(), SOL_SOCKET, SO_RCVBUFFORCE, &size, sizeof size) !=
        0) {
      boost::system::error_code ignored;
      socket_.set_option(asio::socket_base::receive_buffer_size(size), ignored);
    }
    socket_.bind(listen);
    socket_.non_blocking(true);
  }
  udp::endpoint local_endpoint() const { return socket_.local_endpoint(); }
  void start() {
    socket_.async_wait(udp::socket::wait_read, [this](const boost::system::error_code& ec) {
      if (ec == asio::error::operation_aborted)
        return;
      on_readable();
    });
  }

 private:
  void on_readable() {
    if (drain()) {
      start();
      return;
    }
    // Not drained yet: come back after the other handlers (timers, signals) had their turn.
    // Waiting for readability instead could wait long: the socket's edge was used up, and a
    // full socket drops new datagrams without signalling.
    asio::post(socket_.get_executor(), [this] { on_readable(); });
  }

  /// Takes up to kBatch datagrams per recvmmsg call: at 100k states/s the per-call cost of the
  /// system call, not the datagram, is what counts. Returns whether the socket is empty.
  bool drain() {
    for (int round = 0; round < 16; ++round) {  // bounded, so that timers still get their turn
      for (std::size_t i = 0; i < kBatch; ++i) {
        iov_[i] = {buffers_[i].data(), buffers_[i].size()};
        msgs_[i].msg_hdr = {};
        msgs_[i].msg_hdr.msg_iov = &iov_[i];
        msgs_[i].msg_hdr.msg_iovlen = 1;
      }
      const int n =
          ::recvmmsg(socket_.native_handle(), msgs_.data(), kBatch, MSG_DONTWAIT, nullptr);
      if (n <= 0)
        return true;  // EAGAIN: drained (other errors: the next wait reports them again)
      for (int i = 0; i < n; ++i) {
        const auto k = static_cast<std::size_t>(i);
        // A datagram longer than the buffer arrives cut (MSG_TRUNC) and fails the size check.
        const std::span<const std::uint8_t> d(buffers_[k].data(), msgs_[k].msg_len);
        if (relay_)
          relay_->relay_states(d);  // whatever this node makes of it: the next node decides
        if (emulator_.handle_datagram(d))
          for (const auto sink : forward_sinks_)
            // Best effort, like the datagram itself: a full buffer or an absent radio-medium
            // loses this state, never blocks the feeds; its errors are of no one's concern.
            (void)forward_sender_->send(sink, d);
      }
      senders_.flush();
      if (n < static_cast<int>(kBatch))
        return true;
    }
    return false;
  }

  static constexpr std::size_t kBatch = 256;
  udp::socket socket_;
  emu::Emulator& emulator_;
  emu::BatchSenders& senders_;
  emu::BatchSender* forward_sender_ = nullptr;
  std::vector<emu::BatchSender::Sink> forward_sinks_;
  emu::Relay* relay_;
  std::array<mmsghdr, kBatch> msgs_{};
  std::array<iovec, kBatch> iov_{};
  /// Larger than the largest batch a sender makes (wire::kDefaultBatchDatagramSize), so that a
  /// longer datagram arrives cut and fails the batch's count check instead of being misread.
  std::array<std::array<std::uint8_t, 2048>, kBatch> buffers_{};
};

/// The UDP receiver of the signal feed (issue 34): a few datagrams a second, each passed on to
/// the RSUs at once (their sends flushed before the next wait).
class SignalReceiver {
 public:
  SignalReceiver(asio::io_context& io, const udp::endpoint& listen, emu::Emulator& emulator,
                 emu::BatchSenders& senders, emu::Relay* relay)
      : socket_(io), emulator_(emulator), senders_(senders), relay_(relay) {
    socket_.open(listen.protocol());
    socket_.set_option(udp::socket::reuse_address(true));
    socket_.bind(listen);
  }
  udp::endpoint local_endpoint() const { return socket_.local_endpoint(); }
  void start() {
    socket_.async_receive_from(asio::buffer(buffer_), from_,
                               [this](const boost::system::error_code& ec, std::size_t n) {
                                 if (ec == asio::error::operation_aborted)
                                   return;
                                 if (!ec) {
                                   if (relay_)
                                     relay_->relay_signals({buffer_.data(), n});
                                   emulator_.handle_signal_datagram({buffer_.data(), n});
                                   senders_.flush();
                                 }
                                 start();
                               });
  }

 private:
  udp::socket socket_;
  emu::Emulator& emulator_;
  emu::BatchSenders& senders_;
  emu::Relay* relay_;
  udp::endpoint from_;
  /// One more than the largest feed datagram: a longer one arrives cut and fails the decoder.
  std::array<std::uint8_t, wire::kMaxSignalFeedDatagram + 1> buffer_{};
};

/// A relay target's socket, connected so that an absent receiver's ICMP errors come back as
/// this socket's send errors (PeerHealth pauses it).
class ConnectedUdpSink final : public emu::DatagramSink {
 public:
  ConnectedUdpSink(asio::io_context& io, const udp::endpoint& to) : socket_(io, udp::v4()) {
    socket_.non_blocking(true);
    socket_.connect(to);
  }
  std::error_code send(std::span<const std::uint8_t> d) override {
    boost::system::error_code ec;
    socket_.send(asio::buffer(d.data(), d.size()), 0, ec);
    return ec ? std::error_code(ec.value(), std::generic_category()) : std::error_code{};
  }

 private:
  udp::socket socket_;
};

/// Resolves the relay targets' names (swarm's service names, which its DNS may not know yet, and
/// which may move when a service restarts) now and every kInterval, and attaches each target's
/// sockets to the Relay once it resolves or when its address changes.
class RelayResolver {
 public:
  static constexpr std::chrono::seconds kInterval{5};
  RelayResolver(asio::io_context& io, emu::Relay& relay)
      : io_(io), relay_(relay), resolver_(io), timer_(io), slots_(relay.targets().size()) {}
  void start() {
    for (std::size_t k = 0; k < slots_.size(); ++k) {
      const auto& t = relay_.targets()[k];
      resolver_.async_resolve(
          udp::v4(), t.host, std::to_string(t.port),
          [this, k](const boost::system::error_code& ec, udp::resolver::results_type r) {
            if (ec == asio::error::operation_aborted)
              return;
            resolved(k, ec, r);
          });
    }
    timer_.expires_after(kInterval);
    timer_.async_wait([this](const boost::system::error_code& ec) {
      if (!ec)
        start();
    });
  }

 private:
  struct Slot {
    std::optional<udp::endpoint> at;
    std::unique_ptr<ConnectedUdpSink> states, signals;
    bool said_unresolved = false;
  };
  void resolved(std::size_t k, const boost::system::error_code& ec,
                const udp::resolver::results_type& r) {
    Slot& s = slots_[k];
    const auto& t = relay_.targets()[k];
    if (ec || r.empty()) {
      if (!s.said_unresolved && !s.at)
        spdlog::warn("relay {}: the name does not resolve ({}); retrying every {} s", t.text(),
                     ec ? ec.message() : "no address", kInterval.count());
      s.said_unresolved = true;
      return;  // a name that stops resolving keeps its last address
    }
    const udp::endpoint ep = r.begin()->endpoint();
    if (s.at == ep)
      return;
    try {
      auto states = std::make_unique<ConnectedUdpSink>(io_, ep);
      auto signals = std::make_unique<ConnectedUdpSink>(
          io_, udp::endpoint(ep.address(), static_cast<unsigned short>(ep.port() + 1)));
      relay_.attach(k, *states, *signals);
      s.states = std::move(states);
      s.signals = std::move(signals);
      s.at = ep;
      spdlog::info("relay {}: vehicle states to {}:{}, signal feed to port {}", t.text(),
                   ep.address().to_string(), ep.port(), ep.port() + 1);
    } catch (const boost::system::system_error& e) {
      spdlog::warn("relay {}: cannot send to {}: {}", t.text(), ep.address().to_string(),
                   e.code().message());
    }
  }
  asio::io_context& io_;
  emu::Relay& relay_;
  udp::resolver resolver_;
  asio::steady_timer timer_;
  std::vector<Slot> slots_;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"network-emulator: GPS receivers and CAN buses of the testbed's vehicles"};
  std::string scenario_file, listen = "0.0.0.0:4700", stations_file, can_mode = "auto";
  std::string dbc_file = TESTBED_VEHICLE_DBC, trace_file, log_level = "info";
  std::uint64_t seed = 1;
  double status_interval = 5.0;
  int realtime_priority = 0;
  app.add_option("--scenario", scenario_file, "scenario file (JSON)")->required();
  app.add_option("--listen", listen, "UDP address:port for vehicle states")->capture_default_str();
  std::string signals_listen;
  app.add_option("--signals-listen", signals_listen,
                 "UDP address:port for the signal feed from sim-clients (default: --listen's "
                 "port + 1, docs/wire.md)");
  app.add_option("--stations", stations_file,
                 "JSON file: per station address, ports, netns, CAN interface (README)");
  app.add_option("--can", can_mode, "CAN transport")
      ->check(CLI::IsMember({"udp", "vcan", "auto"}))
      ->capture_default_str();
  app.add_option("--dbc", dbc_file, "CAN database")->capture_default_str();
  std::vector<std::string> forward_to;
  app.add_option(
      "--forward", forward_to,
      "pass every valid state on to ADDRESS:PORT (radio-medium --positions; repeatable)");
  std::vector<std::string> relay_to;
  app.add_option("--relay", relay_to,
                 "HOST:PORT, repeatable: pass every vehicle-state datagram on, unchanged, to "
                 "HOST:PORT and every signal-feed datagram to HOST:PORT+1 (another node's "
                 "emulator, issue 35); names are resolved and retried");
  app.add_option("--trace", trace_file, "write trace records (JSON lines) to FILE");
  app.add_option("--seed", seed, "seed of the GNSS error model")->capture_default_str();
  app.add_option("--status-interval", status_interval, "seconds between status lines (0: none)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--realtime-priority", realtime_priority,
                 "run the emulator's thread under SCHED_FIFO at this priority (1..99; 0: normal "
                 "scheduling); refused by the kernel: a warning, and it runs at normal priority")
      ->check(CLI::Range(0, 99));
  app.add_option("--log-level", log_level, "trace, debug, info, warn, error")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error"}))
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  spdlog::set_level(spdlog::level::from_str(log_level));
  spdlog::set_pattern("[%Y-%m-%d %H:%M:%S.%e] [network-emulator] [%l] %v");

  scenario::Scenario scen;
  try {
    scen = scenario::load_file(scenario_file);
  } catch (const scenario::ScenarioError& e) {
    spdlog::error("{}", e.what());
    return scenario::kExitBadScenario;
  }
  auto dbc = can::Database::load(dbc_file);
  if (!dbc) {
    spdlog::error("{}", dbc.error().message());
    return scenario::kExitBadScenario;
  }
  std::vector<emu::StationEndpoints> stations;
  try {
    stations = stations_file.empty() ? emu::default_stations(scen)
                                     : emu::load_stations(stations_file, scen);
  } catch (const emu::StationsConfigError& e) {
    spdlog::error("{}", e.what());
    return scenario::kExitBadScenario;
  }
  const auto listen_ep = parse_endpoint(listen);
  if (!listen_ep) {
    spdlog::error("--listen {}: expected ADDRESS:PORT, e.g. 0.0.0.0:4700", listen);
    return kExitFailure;
  }
  std::optional<udp::endpoint> signals_ep;
  if (signals_listen.empty()) {
    if (listen_ep->port() > 65535 - wire::kSignalFeedPortOffset) {
      spdlog::error(
          "--listen {}: the signal feed's port (+{}) would be beyond 65535; give "
          "--signals-listen",
          listen, wire::kSignalFeedPortOffset);
      return kExitFailure;
    }
    signals_ep =
        udp::endpoint(listen_ep->address(),
                      static_cast<unsigned short>(listen_ep->port() + wire::kSignalFeedPortOffset));
  } else {
    signals_ep = parse_endpoint(signals_listen);
    if (!signals_ep) {
      spdlog::error("--signals-listen {}: expected ADDRESS:PORT, e.g. 0.0.0.0:4701",
                    signals_listen);
      return kExitFailure;
    }
  }
  std::vector<udp::endpoint> forward;
  for (const auto& f : forward_to) {
    const auto ep = parse_endpoint(f);
    if (!ep || !ep->address().is_v4()) {
      spdlog::error("--forward {}: expected IPv4ADDRESS:PORT, e.g. 127.0.0.1:4702", f);
      return kExitFailure;
    }
    forward.push_back(*ep);
  }
  std::vector<emu::RelayTarget> relay_targets;
  for (const auto& r : relay_to) {
    const auto t = emu::parse_relay_target(r);
    if (!t) {
      spdlog::error(
          "--relay {}: expected HOST:PORT with a port from 1 to 65534 (PORT+1 takes the signal "
          "feed), e.g. emulator-tb-node2:4700",
          r);
      return kExitFailure;
    }
    relay_targets.push_back(*t);
  }
  try {
    if (!trace_file.empty())
      trace::configure(trace_file, "network-emulator");
    else
      trace::configure_from_env("network-emulator");
  } catch (const std::exception& e) {
    spdlog::error("--trace {}: {}", trace_file, e.what());
    return kExitFailure;
  }
  raise_fd_limit();

  // CAN transport: SocketCAN where the kernel has it (and --can allows), else cannelloni/UDP.
  bool use_vcan = false;
  if (can_mode == "vcan" || can_mode == "auto") {
    const bool available = can::socketcan_available();
    if (!available && can_mode == "vcan") {
      spdlog::error("--can vcan: this kernel has no SocketCAN (socket(PF_CAN) fails: {})",
                    std::error_code(errno, std::generic_category()).message());
      return kExitFailure;
    }
    use_vcan = available;
  }
  if (use_vcan)
    spdlog::info("CAN transport: SocketCAN (each station's vcan interface){}",
                 can_mode == "auto" ? ", detected" : "");
  else
    spdlog::info("CAN transport: CAN frames over UDP in cannelloni's format ({})",
                 can_mode == "udp" ? "--can udp" : "this kernel has no SocketCAN");

  asio::io_context io;
  // At once: a stop asked for while the stations are set up ends the run cleanly when it starts.
  asio::signal_set signals(io, SIGINT, SIGTERM);
  signals.async_wait([&](const boost::system::error_code& ec, int sig) {
    if (!ec) {
      spdlog::info("signal {}: stopping", sig);
      io.stop();
    }
  });
  clock::AsioRuntime runtime(io);
  // Every UDP feed (NMEA, cannelloni) goes out of a socket of its station's namespace connected
  // to its receiver, in batches; feeds to one receiver share the socket.
  emu::BatchSenders senders;
  auto sender_for = [&](const emu::StationEndpoints& e, const asio::ip::address& addr,
                        std::uint16_t port) -> std::pair<emu::BatchSender*, emu::Destination> {
    const udp::endpoint to(addr, port);
    const auto dest = emu::Destination::from(to.data(), static_cast<socklen_t>(to.size()));
    return {&senders.get_connected(e.netns, dest), dest};
  };
  auto udp_can = [&](const emu::StationEndpoints& e,
                     const asio::ip::address& addr) -> std::unique_ptr<can::CanBus> {
    try {
      const auto [sender, to] = sender_for(e, addr, e.can_port);
      return std::make_unique<emu::BatchedCanBus>(*sender, to);
    } catch (const std::system_error& err) {
      return std::make_unique<BrokenCanBus>(err.code());
    }
  };
  bool logged_fallback = false;
  const emu::StationIoFactory make_io = [&](const emu::StationEndpoints& e) {
    emu::StationIo out;
    const auto addr = asio::ip::make_address(e.address);
    try {
      const auto [sender, to] = sender_for(e, addr, e.gnss_port);
      out.gnss = std::make_unique<emu::BatchedDatagramSink>(*sender, to);
    } catch (const std::system_error& err) {
      out.gnss = std::make_unique<BrokenSink>(err.code());
    }
    if (e.rsu) {  // no CAN bus; its junction's signal states instead
      try {
        const auto [sender, to] = sender_for(e, addr, e.signal_port);
        out.signals = std::make_unique<emu::BatchedDatagramSink>(*sender, to);
      } catch (const std::system_error& err) {
        out.signals = std::make_unique<BrokenSink>(err.code());
      }
      return out;
    }
    if (!use_vcan) {
      out.can = udp_can(e, addr);
      return out;
    }
    auto bus = can::SocketCanBus::open(io, e.can_interface, e.netns);
    if (bus) {
      out.can = std::move(*bus);
    } else if (can_mode == "auto") {
      // The kernel has CAN but this station has no such interface (the launcher made none):
      // the stand-in serves it, as if the kernel had no CAN.
      if (!logged_fallback) {
        logged_fallback = true;
        spdlog::info(
            "station {}: no CAN interface {}{} ({}); CAN over UDP for it and for every "
            "other station without one",
            e.station_id, e.can_interface, e.netns.empty() ? "" : " in netns " + e.netns,
            bus.error().message());
      }
      out.can = udp_can(e, addr);
    } else {
      spdlog::warn("station {}: cannot open CAN interface {}{}: {}", e.station_id, e.can_interface,
                   e.netns.empty() ? "" : " in netns " + e.netns, bus.error().message());
      out.can = std::make_unique<BrokenCanBus>(bus.error());
    }
    return out;
  };

  std::unique_ptr<emu::Emulator> emulator;
  try {
    emulator = std::make_unique<emu::Emulator>(scen, *dbc, stations, make_io, runtime,
                                               trace::global(), seed);
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return scenario::kExitBadScenario;
  }

  std::unique_ptr<emu::Relay> relay;
  std::unique_ptr<RelayResolver> relay_resolver;
  if (!relay_targets.empty()) {
    relay = std::make_unique<emu::Relay>(runtime, relay_targets);
    relay->set_events([](const emu::RelayTarget& t, bool up, const std::string& why) {
      if (up)
        spdlog::info("relay {}: {}", t.text(), why);
      else
        spdlog::warn("relay {}: not taking datagrams ({}); paused, retried every second", t.text(),
                     why);
    });
    relay_resolver = std::make_unique<RelayResolver>(io, *relay);
    relay_resolver->start();
  }
  std::unique_ptr<StateReceiver> receiver;
  try {
    receiver =
        std::make_unique<StateReceiver>(io, *listen_ep, *emulator, senders, forward, relay.get());
  } catch (const boost::system::system_error& e) {
    spdlog::error("cannot listen for vehicle states on {}: {}", listen, e.code().message());
    return kExitFailure;
  } catch (const std::system_error& e) {
    spdlog::error("cannot make the socket for --forward: {}", e.code().message());
    return kExitFailure;
  }
  receiver->start();
  std::unique_ptr<SignalReceiver> signal_receiver;
  try {
    signal_receiver =
        std::make_unique<SignalReceiver>(io, *signals_ep, *emulator, senders, relay.get());
    signal_receiver->start();
  } catch (const boost::system::system_error& e) {
    // Without RSUs nobody needs the feed: a default port taken by another program (tests pick
    // a free --listen port, not a free pair) is not worth stopping for.
    if (!signals_listen.empty() || emulator->rsu_count() > 0) {
      spdlog::error("cannot listen for the signal feed on {}:{}: {}",
                    signals_ep->address().to_string(), signals_ep->port(), e.code().message());
      return kExitFailure;
    }
    spdlog::warn("signal feed off: cannot listen on {}:{} ({}), and the scenario has no RSU",
                 signals_ep->address().to_string(), signals_ep->port(), e.code().message());
    signal_receiver.reset();
  }
  for (const auto& f : forward_to)
    spdlog::info("passing vehicle states on to {}", f);
  spdlog::info("scenario {} ({}): {} stations, GNSS {} Hz, CAN {}/{} Hz; listening on {}",
               scen.name, scenario_file, emulator->station_count(), scen.rates.gnss_hz,
               scen.rates.can_dynamics_hz, scen.rates.can_body_hz,
               fmt::format("{}:{}", receiver->local_endpoint().address().to_string(),
                           receiver->local_endpoint().port()));
  if (signal_receiver)
    spdlog::info("signal feed: listening on {}:{}, {} RSUs",
                 signal_receiver->local_endpoint().address().to_string(),
                 signal_receiver->local_endpoint().port(), emulator->rsu_count());

  // The emulator's counters, then the sockets': datagrams the kernel took, and those it did not
  // (buffer full, an error of their own destination), and the ICMP errors read.
  auto status_line = [&] {
    const emu::BatchStats b = senders.stats();
    return fmt::format(
        "{} | UDP out {} datagrams in {} sendmmsg on {} sockets, dropped {} failed {}, ICMP "
        "errors {}",
        emulator->status_line(), b.sent, b.calls, senders.sockets(), b.dropped, b.failed,
        b.late_errors);
  };
  std::function<void()> status;
  if (status_interval > 0) {
    const auto every =
        std::chrono::duration_cast<clock::Duration>(std::chrono::duration<double>(status_interval));
    status = [&, every] {  // every by value: this block ends before the timer fires
      spdlog::info("{}", status_line());
      trace::global().flush();
      runtime.schedule_in(every, status);
    };
    runtime.schedule_in(every, status);
  }

  if (realtime_priority != 0) {
    // The emulated receivers and buses are hardware of their own in a car: their epochs must
    // not wait for a core behind the stations they feed (docs/latency.md, Round 7). Set last,
    // so that the set-up does not run at it.
    if (const auto r = run_at_realtime_priority(realtime_priority))
      spdlog::info("real-time scheduling: {} priority {}", r->policy, r->priority);
    else
      spdlog::warn(
          "--realtime-priority: cannot run at real-time priority: {}; running at normal "
          "priority (epochs wait for this process to be scheduled)",
          r.error());
  }
  io.run();
  spdlog::info("final: {}", status_line());
  trace::global().flush();
  return EXIT_SUCCESS;
}
