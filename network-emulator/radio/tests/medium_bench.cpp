// radio-medium-bench: throughput and added latency of the veth stand-in medium, through real
// veth pairs and network namespaces. Needs root. Usage: radio-medium-bench [--repetitions N]
// [--frames N] [--samples N] [--pin]. Results in README.md ("Performance").

#include <poll.h>
#include <pthread.h>
#include <sched.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <memory>
#include <thread>
#include <vector>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>
#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>

#include "common/clock/asio_runtime.hpp"
#include "network-emulator/radio/bridge_medium.hpp"
#include "network-emulator/radio/channel.hpp"
#include "network-emulator/radio/medium.hpp"
#include "network-emulator/radio/netns.hpp"
#include "network-emulator/radio/packet_socket.hpp"
#include "network-emulator/radio/rtnl.hpp"
#include "network-emulator/radio/veth_ports.hpp"
#include "network-emulator/radio/veth_radios.hpp"

namespace radio = tb::emu::radio;

namespace {

std::int64_t mono_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec * 1'000'000'000LL + ts.tv_nsec;
}
// CPU time another thread has used so far.
std::int64_t cpu_ns_of(std::thread& t) {
  clockid_t cid;
  pthread_getcpuclockid(t.native_handle(), &cid);
  timespec ts{};
  clock_gettime(cid, &ts);
  return ts.tv_sec * 1'000'000'000LL + ts.tv_nsec;
}

// A fresh, anonymous network namespace kept alive by an open descriptor: no `ip netns` needed.
struct AnonNetns {
  radio::NetnsFd fd;
  std::string path;  // /proc/PID/fd/N, which NetnsFd::open reopens
  AnonNetns() {
    std::thread([this] {
      if (unshare(CLONE_NEWNET) != 0)
        throw std::runtime_error("unshare(CLONE_NEWNET) failed: needs root");
      fd = radio::NetnsFd::current();
    }).join();
    path = "/proc/" + std::to_string(getpid()) + "/fd/" + std::to_string(fd.fd());
  }
};

std::unique_ptr<radio::PacketSocket> open_in(const AnonNetns& ns, const std::string& ifname) {
  return radio::in_netns(radio::NetnsFd::open(ns.path), [&] {
    return std::make_unique<radio::PacketSocket>(ifname, radio::kEthertypeGeoNetworking, 32 << 20);
  });
}

std::vector<std::uint8_t> frame(std::uint32_t seq, std::int64_t ts) {
  std::vector<std::uint8_t> f(128, 0);
  std::fill_n(f.begin(), 6, 0xff);
  f[6] = 0x02;
  f[12] = 0x89;
  f[13] = 0x47;
  std::memcpy(&f[14], &seq, 4);
  std::memcpy(&f[18], &ts, 8);
  return f;
}

bool g_pin = false;

void pin_to(int cpu) {
  if (!g_pin)
    return;
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu % static_cast<int>(std::thread::hardware_concurrency()), &set);
  pthread_setaffinity_np(pthread_self(), sizeof set, &set);
}

struct Percentiles {
  double median = 0, p99 = 0, max = 0;
};
Percentiles percentiles(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  auto at = [&](double q) { return v[static_cast<std::size_t>(q * (v.size() - 1))]; };
  return {at(0.5), at(0.99), v.back()};
}

// One in flight at a time: send timestamp in the frame, receive timestamp taken by the
// receiving station's thread as soon as recv returns.
std::vector<double> latency_us(radio::PacketSocket& tx, radio::PacketSocket& rx, int samples) {
  std::vector<double> out;
  out.reserve(samples);
  std::array<std::uint8_t, 2048> buf{};
  for (int i = 0; i < samples; ++i) {
    tx.send(frame(static_cast<std::uint32_t>(i), mono_ns()));
    for (;;) {
      const long n = rx.receive(buf, /*wait=*/true);
      if (n < 26)
        continue;
      std::uint32_t seq;
      std::int64_t ts;
      std::memcpy(&seq, &buf[14], 4);
      std::memcpy(&ts, &buf[18], 8);
      if (seq != static_cast<std::uint32_t>(i))
        continue;
      out.push_back(static_cast<double>(mono_ns() - ts) / 1000.0);
      break;
    }
  }
  return out;
}

std::int64_t thread_cpu_ns() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec * 1'000'000'000LL + ts.tv_nsec;
}

}  // namespace

int main(int argc, char** argv) {
  int repetitions = 10, frames = 50'000, samples = 5'000, stations = 3;
  std::string forwarding = "user";
  CLI::App app{"radio-medium-bench: throughput and latency of the veth stand-in medium"};
  app.add_option("--repetitions", repetitions)->check(CLI::PositiveNumber);
  app.add_option("--frames", frames, "frames per throughput run")->check(CLI::PositiveNumber);
  app.add_option("--samples", samples, "frames per latency run")->check(CLI::PositiveNumber);
  app.add_option("--stations", stations, "stations on the medium (one sends, all hear)")
      ->check(CLI::Range(3, 1000));
  app.add_option("--forwarding", forwarding,
                 "user: radio-medium's own forwarding (VethPorts, sendmmsg); kernel: the bridge")
      ->check(CLI::IsMember({"user", "kernel"}));
  app.add_flag("--pin", g_pin, "medium thread on CPU 0, stations on CPU 1 (an idle machine)");
  CLI11_PARSE(app, argc, argv);
  spdlog::set_level(spdlog::level::warn);
  if (geteuid() != 0) {
    std::fprintf(stderr, "radio-medium-bench: needs root (namespaces, veth)\n");
    return 1;
  }
  try {
    std::vector<std::unique_ptr<AnonNetns>> ns;
    std::vector<radio::StationSpec> specs;
    for (int i = 0; i < stations; ++i) {
      ns.push_back(std::make_unique<AnonNetns>());
      specs.push_back({static_cast<radio::StationId>(i + 1), ns.back()->path});
    }
    const AnonNetns& a = *ns.front();
    const AnonNetns& b = *ns[1];
    const AnonNetns& last = *ns.back();
    // The baseline: a direct veth pair between a and b, no medium between them.
    radio::in_netns(radio::NetnsFd::open(a.path), [&] {
      radio::RouteSocket rtnl;
      rtnl.add_veth("direct0", "bench", "direct0", radio::NetnsFd::open(b.path).fd(),
                    radio::station_mac(99));
      rtnl.set_up("direct0");
    });
    radio::in_netns(radio::NetnsFd::open(b.path), [] { radio::RouteSocket().set_up("direct0"); });

    const std::string prefix = "tbb" + std::to_string(getpid() % 100);
    radio::VethRadios veths(specs, prefix);
    tb::scenario::ChannelModel ideal;
    radio::PositionTable positions;
    radio::Channel channel(ideal, positions, 1);
    boost::asio::io_context io;
    tb::clock::AsioRuntime runtime(io);
    radio::Medium medium(runtime, channel);
    std::unique_ptr<radio::VethPorts> ports;
    std::unique_ptr<radio::BridgeMedium> bridge;
    if (forwarding == "kernel") {
      bridge = std::make_unique<radio::BridgeMedium>(io, prefix + "br", "bench",
                                                     radio::kEthertypeGeoNetworking, channel);
      for (const auto& s : specs)
        bridge->attach(s.id, veths.host_ifname(s.id));
      bridge->start();
    } else {
      ports = std::make_unique<radio::VethPorts>(io, radio::kEthertypeGeoNetworking, medium);
      for (const auto& s : specs)
        ports->attach(s.id, veths.host_ifname(s.id));
      ports->start();
    }
    auto guard = boost::asio::make_work_guard(io);
    // The medium gets a core of its own, the stations share the other: "on one core".
    std::thread medium_thread([&] {
      pin_to(0);
      io.run();
    });

    pin_to(1);
    auto wa = open_in(a, radio::kStationIfname);
    auto wb = open_in(b, radio::kStationIfname);
    auto wc = open_in(last, radio::kStationIfname);
    auto da = open_in(a, "direct0");
    auto db = open_in(b, "direct0");

    std::vector<double> direct_median, medium_median, medium_p99, medium_max, direct_p99;
    std::vector<double> tput, tput_deliv, medium_cpu_us, sender_cpu_us;
    std::printf(
        "%d stations, forwarding %s; latency to the last of %d receivers\n"
        "run  direct-veth µs (median p99)  via medium µs (median p99 max)  "
        "frames/s in  CPU µs per frame (medium thread, sender)\n",
        stations, forwarding.c_str(), stations - 1);
    for (int r = 0; r < repetitions; ++r) {
      const auto d = percentiles(latency_us(*da, *db, samples));
      const auto m = percentiles(latency_us(*wa, *wc, samples));
      direct_median.push_back(d.median);
      direct_p99.push_back(d.p99);
      medium_median.push_back(m.median);
      medium_p99.push_back(m.p99);
      medium_max.push_back(m.max);

      // Throughput: station a sends to every other station, at most a window ahead of the
      // slower of two receivers (the first and the last port) so that nothing is lost to full
      // buffers.
      std::atomic<std::uint64_t> got_b{0}, got_c{0};
      std::atomic<bool> stop{false};
      auto drain = [&](radio::PacketSocket& s, std::atomic<std::uint64_t>& got) {
        pin_to(1);
        std::array<std::uint8_t, 2048> buf{};
        while (!stop) {
          pollfd p{s.fd(), POLLIN, 0};
          if (::poll(&p, 1, 50) <= 0)
            continue;
          while (s.receive(buf) > 0)
            ++got;
        }
      };
      std::thread rb(drain, std::ref(*wb), std::ref(got_b));
      std::thread rc(drain, std::ref(*wc), std::ref(got_c));
      const std::int64_t cpu0 = cpu_ns_of(medium_thread);
      const std::int64_t send_cpu0 = thread_cpu_ns();
      const std::int64_t t0 = mono_ns();
      const auto f = frame(0, 0);
      for (int i = 0; i < frames; ++i) {
        while (static_cast<std::uint64_t>(i) - std::min(got_b.load(), got_c.load()) > 256)
          std::this_thread::yield();
        wa->send(f);
      }
      const std::int64_t send_cpu1 = thread_cpu_ns();
      while (std::min(got_b.load(), got_c.load()) < static_cast<std::uint64_t>(frames) &&
             mono_ns() - t0 < 30'000'000'000LL)
        std::this_thread::yield();
      const std::int64_t t1 = mono_ns();
      const std::int64_t cpu1 = cpu_ns_of(medium_thread);
      stop = true;
      rb.join();
      rc.join();
      const double secs = static_cast<double>(t1 - t0) / 1e9;
      tput.push_back(frames / secs);
      tput_deliv.push_back(static_cast<double>(got_b + got_c) / secs);
      medium_cpu_us.push_back(static_cast<double>(cpu1 - cpu0) / 1e3 / frames);
      // The sender's send carries the frame through the kernel: with the bridge, into every
      // receiver; with the userspace medium, to its socket. The busy-wait is a few % of it.
      sender_cpu_us.push_back(static_cast<double>(send_cpu1 - send_cpu0) / 1e3 / frames);
      std::printf("%3d  %8.1f %8.1f              %8.1f %8.1f %8.1f          %9.0f  %7.2f %7.2f\n",
                  r, d.median, d.p99, m.median, m.p99, m.max, tput.back(), medium_cpu_us.back(),
                  sender_cpu_us.back());
      std::fflush(stdout);
    }
    guard.reset();
    io.stop();
    medium_thread.join();
    if (bridge)
      bridge->drain_all();

    auto med = [](std::vector<double> v) { return percentiles(std::move(v)).median; };
    auto mx = [](const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()); };
    auto mn = [](const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); };
    std::printf("\nover %d runs (median of runs; min..max):\n", repetitions);
    std::printf("  latency direct veth   median %.1f µs, p99 %.1f µs\n", med(direct_median),
                med(direct_p99));
    std::printf("  latency via medium    median %.1f µs, p99 %.1f µs, max %.1f µs\n",
                med(medium_median), med(medium_p99), mx(medium_max));
    std::printf("  added by the medium   median %.1f µs\n",
                med(medium_median) - med(direct_median));
    std::printf(
        "  throughput            %.0f frames/s in (%.0f..%.0f), %.0f deliveries/s at the "
        "two watched receivers\n",
        med(tput), mn(tput), mx(tput), med(tput_deliv));
    std::printf("  CPU per frame in      medium thread %.2f µs, sender %.2f µs (%d deliveries)\n",
                med(medium_cpu_us), med(sender_cpu_us), stations - 1);
    const auto totals = channel.totals();
    std::printf("  channel: %llu sent, %llu delivered, %llu dropped\n",
                static_cast<unsigned long long>(totals.sent),
                static_cast<unsigned long long>(totals.delivered),
                static_cast<unsigned long long>(totals.dropped_total()));
    if (bridge) {
      std::uint64_t dropped = 0;
      for (const auto& [id, n] : bridge->kernel_drops())
        dropped += n;
      std::printf("  kernel: %llu deliveries dropped, tap missed %llu frames\n",
                  static_cast<unsigned long long>(dropped),
                  static_cast<unsigned long long>(bridge->tap_drops()));
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "radio-medium-bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
