// State fan-out bench: the real sim-server with 100 cars at 100 Hz, 50 loopback clients
// watching. For every State frame each client receives it records how long after the step it
// arrived: after the frame was stamped for sending (send_wall_ns, right after the step) and
// after the step began (step_wall_ns). Prints median, p90, p99 and max in milliseconds.
//
//   sim_fanout_bench [--clients 50] [--vehicles 100] [--seconds 10] [--server PATH]

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <CLI/CLI.hpp>
#include <boost/asio.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <thread>
#include <vector>

#include "common/clock/clock.hpp"
#include "common/util/bytes.hpp"
#include "common/wire/sim_protocol.hpp"

extern char** environ;

namespace asio = boost::asio;
namespace sim = tb::wire::sim;
using asio::ip::tcp;

namespace {

std::int64_t now_ns() {
  return tb::clock::to_unix_ns(tb::clock::WallClock::now());
}

struct Samples {
  std::vector<double> after_send_ms, after_step_ms;
  std::size_t frames = 0;
};

class Watcher {
 public:
  Watcher(asio::io_context& io, Samples& out) : socket_(io), out_(out) {}
  bool connect(std::uint16_t port) {
    boost::system::error_code ec;
    socket_.connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), port), ec);
    if (ec)
      return false;
    auto hello = sim::encode(sim::Hello{"fanout-bench"});
    auto attach = sim::encode(sim::Attach{sim::Role::kWatcher, 0});
    hello.insert(hello.end(), attach.begin(), attach.end());
    asio::write(socket_, asio::buffer(hello), ec);
    read();
    return !ec;
  }
  bool measuring = false;

 private:
  void read() {
    socket_.async_read_some(asio::buffer(buf_), [this](boost::system::error_code ec,
                                                       std::size_t n) {
      if (ec)
        return;
      const std::int64_t t = now_ns();
      std::span<const std::uint8_t> data(buf_.data(), n);
      while (!data.empty()) {
        auto r = parser_.parse(data);
        if (!r) {
          std::fprintf(stderr, "bad frame: %s\n", std::string(sim::to_string(r.error())).c_str());
          return;
        }
        if (*r != sim::FrameParser::Status::kFrame)
          break;
        const auto& f = parser_.frame();
        if (f.type != sim::MessageType::kState || !measuring)
          continue;
        // Only the frame head and the first record are needed for the time stamps.
        tb::ByteReader h(f.payload);
        h.skip(16);
        const auto step_wall = h.le<std::int64_t>();
        h.skip(2);
        auto first =
            tb::wire::decode(h.rest().first(std::min(h.remaining(), tb::wire::kVehicleStateSize)));
        if (!first)
          continue;
        out_.after_send_ms.push_back((t - first->send_wall_ns) * 1e-6);
        out_.after_step_ms.push_back((t - step_wall) * 1e-6);
        ++out_.frames;
      }
      read();
    });
  }

  tcp::socket socket_;
  Samples& out_;
  std::array<std::uint8_t, 1 << 16> buf_{};
  sim::FrameParser parser_{sim::Sender::kServer};
};

void report(const char* what, std::vector<double> v) {
  if (v.empty()) {
    std::printf("%s: no samples\n", what);
    return;
  }
  std::sort(v.begin(), v.end());
  auto q = [&v](double p) {
    return v[std::min(v.size() - 1, static_cast<std::size_t>(p * v.size()))];
  };
  std::printf("%-34s n=%zu median %.3f ms  p90 %.3f ms  p99 %.3f ms  max %.3f ms\n", what, v.size(),
              q(0.5), q(0.9), q(0.99), v.back());
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"sim-server state fan-out latency"};
  int clients = 50, vehicles = 100;
  double seconds = 10;
  std::string server =
      (std::filesystem::path(argv[0]).parent_path() / ".." / "bin" / "sim-server").string();
  app.add_option("--clients", clients)->capture_default_str();
  app.add_option("--vehicles", vehicles)->capture_default_str();
  app.add_option("--seconds", seconds)->capture_default_str();
  app.add_option("--server", server)->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  // A scenario with the cars spread over four lanes, 10 m apart along the road.
  const auto dir =
      std::filesystem::temp_directory_path() / ("fanout-bench-" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const auto file = (dir / "scenario.json").string();
  {
    std::ofstream out(file);
    out << R"({"name":"fan-out bench","map":{"type":"straight","lanes":4,"oncoming_lanes":0,)"
        << R"("length":)" << 100 + vehicles * 10 << R"(},"origin":{"lat":41.1,"lon":29.0,"alt":0},)"
        << R"("vehicles":[)";
    for (int i = 0; i < vehicles; ++i) {
      out << (i ? "," : "") << R"({"id":"v)" << i << R"(","station_id":)" << 1000 + i
          << R"(,"spawn":{"lane":)" << i % 4 << R"(,"s":)" << 20 + i * 10
          << R"(,"speed":10},"driver":"human"})";
    }
    out << "]}";
  }
  std::uint16_t port;
  {
    asio::io_context io;
    tcp::acceptor a(io, tcp::endpoint(asio::ip::make_address("127.0.0.1"), 0));
    port = a.local_endpoint().port();
  }
  std::vector<std::string> args = {
      server,        "--scenario", file,      "--port", std::to_string(port), "--bind", "127.0.0.1",
      "--log-level", "warn",       "--queue", "1000"};
  std::vector<char*> cargs;
  for (auto& s : args)
    cargs.push_back(s.data());
  cargs.push_back(nullptr);
  pid_t pid;
  if (posix_spawn(&pid, cargs[0], nullptr, nullptr, cargs.data(), environ) != 0) {
    std::fprintf(stderr, "cannot start %s\n", server.c_str());
    return 1;
  }

  asio::io_context io;
  Samples samples;
  std::vector<std::unique_ptr<Watcher>> watchers;
  for (int i = 0; i < clients; ++i) {
    auto w = std::make_unique<Watcher>(io, samples);
    bool ok = false;
    for (int k = 0; k < 200 && !(ok = w->connect(port)); ++k) {
      w = std::make_unique<Watcher>(io, samples);
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    if (!ok) {
      std::fprintf(stderr, "cannot connect to the server on port %u\n", port);
      kill(pid, SIGKILL);
      return 1;
    }
    watchers.push_back(std::move(w));
  }
  // One second to settle, then measure.
  io.run_for(std::chrono::seconds(1));
  for (auto& w : watchers)
    w->measuring = true;
  io.run_for(std::chrono::milliseconds(static_cast<int>(seconds * 1000)));
  kill(pid, SIGTERM);
  int status = 0;
  waitpid(pid, &status, 0);
  std::filesystem::remove_all(dir);

  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    std::fprintf(stderr, "sim-server exited with status %d\n", status);
  if (samples.frames == 0) {
    std::fprintf(stderr, "no State frames arrived\n");
    return 1;
  }
  std::printf(
      "%d clients, %d vehicles, %.0f s: %zu State frames received (%.0f per client per s)\n",
      clients, vehicles, seconds, samples.frames, samples.frames / seconds / clients);
  report("arrival after send stamp", samples.after_send_ms);
  report("arrival after step start", samples.after_step_ms);
  return 0;
}
