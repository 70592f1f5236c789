// What a CAN stand-in socket read on demand costs the thread that runs the io_context while
// datagrams arrive at 100 Hz and nobody waits on it (issue 33): the socket left registered with
// the io_context (as UdpCanBus was until it released it: each datagram an epoll event, a
// wake-up with nothing to do) against UdpCanBus::start_on_demand. Each iteration sends ten
// datagrams 10 ms apart from the benchmark's thread (100 ms of a vehicle's CAN stream), then
// reads them from that thread, as a station's handlers would at their next poll. Read the
// counters: the io thread's CPU in µs and its voluntary context switches, per second of stream.
#include <pthread.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <ctime>
#include <fstream>
#include <string>
#include <thread>

#include <benchmark/benchmark.h>
#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <boost/asio/post.hpp>

#include "common/can/udp_can_bus.hpp"

namespace {

using udp = boost::asio::ip::udp;

/// The io_context's thread, with its CPU clock and its voluntary context switches.
class IoThread {
 public:
  IoThread() : guard_(io_.get_executor()), thread_([this] { run(); }) {
    while (tid_.load() == 0)
      std::this_thread::yield();
  }
  ~IoThread() {
    guard_.reset();
    io_.stop();
    thread_.join();
  }
  boost::asio::io_context& io() { return io_; }
  double cpu_us() {
    clockid_t id{};
    pthread_getcpuclockid(thread_.native_handle(), &id);
    timespec ts{};
    clock_gettime(id, &ts);
    return static_cast<double>(ts.tv_sec) * 1e6 + static_cast<double>(ts.tv_nsec) / 1e3;
  }
  long voluntary_switches() const {
    std::ifstream status("/proc/self/task/" + std::to_string(tid_.load()) + "/status");
    for (std::string line; std::getline(status, line);)
      if (line.starts_with("voluntary_ctxt_switches:"))
        return std::stol(line.substr(line.find(':') + 1));
    return -1;
  }

 private:
  void run() {
    tid_ = static_cast<long>(::syscall(SYS_gettid));
    io_.run();
  }
  boost::asio::io_context io_;
  boost::asio::executor_work_guard<boost::asio::io_context::executor_type> guard_;
  std::atomic<long> tid_{0};
  std::thread thread_;
};

void BM_CanStreamAt100Hz(benchmark::State& state) {
  const bool released = state.range(0) != 0;
  IoThread io;
  const udp::endpoint local{boost::asio::ip::make_address("127.0.0.1"), 0};
  std::unique_ptr<tb::can::UdpCanBus> bus;
  std::unique_ptr<udp::socket> registered;
  udp::endpoint to;
  std::size_t frames = 0;
  if (released) {
    bus = tb::can::UdpCanBus::bind(io.io(), local);
    bus->start_on_demand([&](const tb::can::CanFrame&, std::int64_t) { ++frames; },
                         std::chrono::hours{1});
    to = bus->local_endpoint();
  } else {
    registered = std::make_unique<udp::socket>(io.io(), local);
    registered->non_blocking(true);
    to = registered->local_endpoint();
  }
  udp::socket tx(io.io(), udp::v4());
  const std::uint8_t datagram[] = {2, 0, 0, 0, 1, 0, 0, 1, 0, 8, 1, 2, 3, 4, 5, 6, 7, 8};
  std::uint8_t sink[2048];
  double cpu = 0;
  long switches = 0;
  for (auto _ : state) {
    const double cpu0 = io.cpu_us();
    const long sw0 = io.voluntary_switches();
    auto next = std::chrono::steady_clock::now();
    for (int i = 0; i < 10; ++i) {
      next += std::chrono::milliseconds{10};
      std::this_thread::sleep_until(next);
      tx.send_to(boost::asio::buffer(datagram), to);
    }
    cpu += io.cpu_us() - cpu0;
    switches += io.voluntary_switches() - sw0;
    if (bus) {
      bus->poll();
    } else {
      boost::system::error_code ec;
      udp::endpoint from;
      while (!ec)
        registered->receive_from(boost::asio::buffer(sink), from, 0, ec);
    }
  }
  const double seconds = static_cast<double>(state.iterations()) * 0.1;
  state.counters["io_cpu_us_per_s"] = cpu / seconds;
  state.counters["io_wakeups_per_s"] = static_cast<double>(switches) / seconds;
  state.SetLabel(released ? "UdpCanBus on demand (released)" : "socket left in the epoll set");
}
BENCHMARK(BM_CanStreamAt100Hz)->Arg(0)->Arg(1)->Iterations(30)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
