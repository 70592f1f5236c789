// Integration test: the real sim-server process from $TESTBED_BIN, three clients over TCP
// driving two cars and watching, one driver leaving (its car stops), garbage on a fourth
// connection (only that one is closed), a refused second driver, and SIGTERM.

#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <boost/asio.hpp>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <fstream>
#include <functional>
#include <future>
#include <iterator>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <type_traits>

#include "common/wire/sim_protocol.hpp"

extern char** environ;

namespace tb::server {
namespace {

namespace asio = boost::asio;
namespace sim = wire::sim;
using asio::ip::tcp;
using namespace std::chrono_literals;

std::string bin(const std::string& name) {
  const char* dir = std::getenv("TESTBED_BIN");
  return std::string(dir ? dir : "build/bin") + "/" + name;
}

std::uint16_t free_port() {
  asio::io_context io;
  tcp::acceptor a(io, tcp::endpoint(asio::ip::make_address("127.0.0.1"), 0));
  return a.local_endpoint().port();
}

/// The server process; killed in the destructor if the test did not stop it.
class ServerProcess {
 public:
  /// With @p log, the server's output goes to that file (for tests that wait on its messages).
  explicit ServerProcess(std::vector<std::string> args, const std::string& log = {}) {
    args.insert(args.begin(), bin("sim-server"));
    std::vector<char*> argv;
    for (auto& a : args)
      argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    if (!log.empty()) {
      posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      posix_spawn_file_actions_adddup2(&fa, 1, 2);
    }
    if (posix_spawn(&pid_, argv[0], &fa, nullptr, argv.data(), environ) != 0)
      pid_ = -1;
    posix_spawn_file_actions_destroy(&fa);
  }
  ~ServerProcess() {
    if (pid_ > 0 && !exited_) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
  }
  bool started() const { return pid_ > 0; }
  void signal(int sig) { ::kill(pid_, sig); }
  /// Exit status, or nullopt if it is still running after @p timeout.
  std::optional<int> wait(std::chrono::milliseconds timeout) {
    const auto until = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < until) {
      int status = 0;
      if (::waitpid(pid_, &status, WNOHANG) == pid_) {
        exited_ = true;
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      }
      std::this_thread::sleep_for(10ms);
    }
    return std::nullopt;
  }

 private:
  pid_t pid_ = -1;
  bool exited_ = false;
};

/// A protocol client on the shared io thread; what it receives is kept under a mutex.
class Client {
 public:
  Client(asio::io_context& io, std::uint16_t port) : socket_(io) {
    boost::system::error_code ec;
    for (int i = 0; i < 200; ++i) {
      socket_.connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), port), ec);
      if (!ec)
        break;
      socket_.close();
      std::this_thread::sleep_for(25ms);
    }
    connected_ = !ec;
    if (connected_)
      asio::post(socket_.get_executor(), [this] { read(); });
  }
  bool connected() const { return connected_; }

  void send(const sim::ClientMessage& m) { send_raw(sim::encode(m)); }
  void send_raw(std::vector<std::uint8_t> bytes) {
    auto b = std::make_shared<std::vector<std::uint8_t>>(std::move(bytes));
    asio::post(socket_.get_executor(), [this, b] {
      boost::system::error_code ec;
      asio::write(socket_, asio::buffer(*b), ec);
    });
  }
  /// Closes the connection and waits until its read handler has run for the last time, so that
  /// no handler of this client runs after it is gone (the aborted read completes on the io
  /// thread some time after the close).
  void close() {
    if (!connected_)
      return;
    on_io([this] {
      boost::system::error_code ec;
      socket_.shutdown(tcp::socket::shutdown_both, ec);
      socket_.close(ec);
    });
    while (!on_io([this] { return read_ended_; }))
      std::this_thread::sleep_for(1ms);
    connected_ = false;
  }
  ~Client() { close(); }
  Client(const Client&) = delete;
  Client& operator=(const Client&) = delete;

  bool eof() const { return eof_; }
  std::optional<sim::StateFrame> last_state() const {
    std::lock_guard lock(mutex_);
    return last_state_;
  }
  std::vector<sim::ServerMessage> others() const {
    std::lock_guard lock(mutex_);
    return others_;
  }
  /// The latest message of type T.
  template <typename T>
  std::optional<T> find() const {
    std::lock_guard lock(mutex_);
    for (auto it = others_.rbegin(); it != others_.rend(); ++it) {
      if (const auto* x = std::get_if<T>(&*it))
        return *x;
    }
    return std::nullopt;
  }
  template <typename T>
  std::size_t count() const {
    std::lock_guard lock(mutex_);
    return std::count_if(others_.begin(), others_.end(),
                         [](const auto& m) { return std::holds_alternative<T>(m); });
  }
  std::size_t states() const { return states_; }
  /// For each SignalStates in arrival order: the sim time of the State frame before it.
  std::vector<std::optional<std::int64_t>> signals_after() const {
    std::lock_guard lock(mutex_);
    return signals_after_;
  }

 private:
  /// Runs @p f on the io thread and returns its result.
  template <typename F>
  std::invoke_result_t<F> on_io(F f) {
    return asio::post(socket_.get_executor(), asio::use_future(std::move(f))).get();
  }
  void read() {
    socket_.async_read_some(
        asio::buffer(buf_), [this](boost::system::error_code ec, std::size_t n) {
          if (ec) {
            eof_ = true;
            read_ended_ = true;
            return;
          }
          std::span<const std::uint8_t> data(buf_.data(), n);
          while (!data.empty()) {
            auto r = parser_.parse(data);
            if (!r) {
              ADD_FAILURE() << "server sent a bad frame: " << sim::to_string(r.error());
              read_ended_ = true;
              return;
            }
            if (*r != sim::FrameParser::Status::kFrame)
              break;
            auto m = sim::decode_server(parser_.frame());
            if (!m) {
              ADD_FAILURE() << "server sent a bad message: " << sim::to_string(m.error());
              read_ended_ = true;
              return;
            }
            std::lock_guard lock(mutex_);
            if (auto* s = std::get_if<sim::StateFrame>(&*m)) {
              last_state_ = std::move(*s);
              ++states_;
            } else {
              if (std::holds_alternative<sim::SignalStates>(*m))
                signals_after_.push_back(last_state_ ? std::optional(last_state_->sim_time_ns)
                                                     : std::nullopt);
              others_.push_back(std::move(*m));
            }
          }
          read();
        });
  }

  tcp::socket socket_;
  bool connected_ = false;
  std::array<std::uint8_t, 65536> buf_{};
  sim::FrameParser parser_{sim::Sender::kServer};
  mutable std::mutex mutex_;
  std::optional<sim::StateFrame> last_state_;
  std::vector<sim::ServerMessage> others_;
  std::vector<std::optional<std::int64_t>> signals_after_;
  std::atomic<std::size_t> states_{0};
  std::atomic<bool> eof_{false};
  bool read_ended_ = false;  // touched on the io thread only
};

template <typename Pred>
bool eventually(Pred p, std::chrono::milliseconds timeout) {
  const auto until = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < until) {
    if (p())
      return true;
    std::this_thread::sleep_for(20ms);
  }
  return p();
}

TEST(SimServerIT, ThreeClientsDriveWatchAndSurviveGarbage) {
  const auto port = free_port();
  ServerProcess server({"--scenario", "sim-server/tests/scenarios/three-cars.json", "--port",
                        std::to_string(port), "--bind", "127.0.0.1", "--log-level", "warn"});
  ASSERT_TRUE(server.started()) << bin("sim-server");

  asio::io_context io;
  auto work = asio::make_work_guard(io);
  std::thread io_thread([&] { io.run(); });
  {
    Client a(io, port), b(io, port), w(io, port);
    ASSERT_TRUE(a.connected() && b.connected() && w.connected());
    a.send(sim::Hello{"driver-a"});
    b.send(sim::Hello{"driver-b"});
    w.send(sim::Hello{"watcher"});
    ASSERT_TRUE(eventually([&] { return w.find<sim::Welcome>().has_value(); }, 3s));
    EXPECT_EQ(w.find<sim::Welcome>()->vehicles.size(), 3u);
    a.send(sim::Attach{sim::Role::kDriver, 0});
    b.send(sim::Attach{sim::Role::kDriver, 1});
    w.send(sim::Attach{sim::Role::kWatcher, 0});
    ASSERT_TRUE(
        eventually([&] { return a.find<sim::AttachResult>() && b.find<sim::AttachResult>(); }, 2s));
    EXPECT_EQ(a.find<sim::AttachResult>()->status, sim::AttachStatus::kOk);
    EXPECT_EQ(b.find<sim::AttachResult>()->status, sim::AttachStatus::kOk);

    // Both drive, controls at 20 Hz, until both cars are under way and the watcher has seen
    // the stream for a while (a deadline, not a fixed time: a loaded machine is slower).
    auto drive = [](Client& c, std::uint16_t v) {
      c.send(sim::ControlsMsg{v, {0.5f, 0.0f, 0.0f, false, false}, wire::kLowBeam});
    };
    const auto driving = [&] {
      const auto st = w.last_state();
      return st && st->vehicles[0].speed > 2.0f && st->vehicles[1].speed > 2.0f &&
             w.states() > 150u;
    };
    for (const auto until = std::chrono::steady_clock::now() + 20s;
         !driving() && std::chrono::steady_clock::now() < until;) {
      drive(a, 0);
      drive(b, 1);
      std::this_thread::sleep_for(50ms);
    }
    auto s = w.last_state();
    ASSERT_TRUE(s);
    EXPECT_GT(s->vehicles[0].speed, 2.0f);
    EXPECT_GT(s->vehicles[1].speed, 2.0f);
    EXPECT_LT(std::abs(s->vehicles[2].speed), 0.1f) << "nobody drives c: it brakes to a stop";
    EXPECT_GT(w.states(), 150u) << "100 Hz state stream";

    // The watcher may not take over b's car.
    ASSERT_EQ(w.count<sim::AttachResult>(), 1u);
    w.send(sim::Attach{sim::Role::kDriver, 1});
    ASSERT_TRUE(eventually([&] { return w.count<sim::AttachResult>() == 2; }, 2s));
    EXPECT_EQ(w.find<sim::AttachResult>()->status, sim::AttachStatus::kAlreadyDriven);
    EXPECT_NE(w.find<sim::AttachResult>()->reason.find("driver-b"), std::string::npos);

    // Driver a leaves; b keeps driving. Garbage arrives on a fourth connection meanwhile.
    a.close();
    Client g(io, port);
    ASSERT_TRUE(g.connected());
    const std::string junk = "GET / HTTP/1.1\r\nHost: sim-server\r\n\r\n";
    g.send_raw(std::vector<std::uint8_t>(junk.begin(), junk.end()));
    const auto ticks_before = w.states();
    bool a_stopped = false;
    for (const auto until = std::chrono::steady_clock::now() + 20s;
         !a_stopped && std::chrono::steady_clock::now() < until;) {
      drive(b, 1);
      std::this_thread::sleep_for(50ms);
      const auto st = w.last_state();
      a_stopped = st && std::abs(st->vehicles[0].speed) < 0.05f;
    }
    EXPECT_TRUE(a_stopped) << "the car of the driver who left did not stop";
    s = w.last_state();
    EXPECT_TRUE(s->vehicles[0].lights & wire::kBrakeLights);
    EXPECT_TRUE(s->vehicles[0].lights & wire::kHazard);
    EXPECT_GT(s->vehicles[1].speed, 3.0f) << "b's car should still be driving";

    EXPECT_TRUE(eventually([&] { return g.eof(); }, 2s)) << "garbage connection not closed";
    const auto closing = g.find<sim::Closing>();
    ASSERT_TRUE(closing);
    EXPECT_EQ(closing->reason, sim::CloseReason::kProtocolError);
    EXPECT_FALSE(b.eof());
    EXPECT_FALSE(w.eof());
    EXPECT_TRUE(eventually([&] { return w.states() > ticks_before + 50; }, 5s))
        << "the stream went on for the others";

    // SIGTERM: everyone gets Closing(shutdown), the server exits 0.
    server.signal(SIGTERM);
    const auto rc = server.wait(5s);
    ASSERT_TRUE(rc) << "server did not stop on SIGTERM";
    EXPECT_EQ(*rc, 0);
    EXPECT_TRUE(eventually([&] { return b.eof() && w.eof(); }, 2s));
    ASSERT_TRUE(w.find<sim::Closing>());
    EXPECT_EQ(w.find<sim::Closing>()->reason, sim::CloseReason::kShutdown);
    b.close();
    w.close();
  }
  work.reset();
  io.stop();
  io_thread.join();
}

TEST(SimServerIT, WarmUpWaitsForTheScriptedDriverThenHoldsTheCarsOnTheirRunUps) {
  const auto port = free_port();
  ServerProcess server({"--scenario", "sim-server/tests/scenarios/warm-up.json", "--port",
                        std::to_string(port), "--bind", "127.0.0.1", "--log-level", "warn"});
  ASSERT_TRUE(server.started()) << bin("sim-server");
  asio::io_context io;
  auto work = asio::make_work_guard(io);
  std::thread io_thread([&] { io.run(); });
  {
    Client w(io, port), d(io, port);
    ASSERT_TRUE(w.connected() && d.connected());
    w.send(sim::Hello{"watcher"});
    w.send(sim::Attach{sim::Role::kWatcher, 0});
    d.send(sim::Hello{"script"});
    ASSERT_TRUE(eventually([&] { return w.find<sim::AttachResult>().has_value(); }, 3s));
    // Nobody drives the scripted car yet: the first step waits. At 100 Hz a running physics
    // would have sent 30 states in this time.
    std::this_thread::sleep_for(300ms);
    EXPECT_EQ(w.states(), 0u) << "the physics started before the scripted car had its driver";

    d.send(sim::Attach{sim::Role::kDriver, 1});
    ASSERT_TRUE(eventually([&] { return w.states() > 0; }, 3s));
    // The warm-up: negative sim time, the rolling car on its run-up at 10 m/s to s = 50 (x =
    // 50), the scripted car standing although its driver asks for full throttle.
    std::optional<sim::StateFrame> warm;
    for (int i = 0; i < 10; ++i) {
      d.send(sim::ControlsMsg{1, {1.0f, 0.0f, 0.0f, false, false}, 0, 0});
      std::this_thread::sleep_for(20ms);
      if (auto s = w.last_state(); s && s->sim_time_ns < 0)
        warm = s;
    }
    ASSERT_TRUE(warm) << "no state of the warm-up";
    EXPECT_GE(warm->sim_time_ns, -1'000'000'000);
    const double t = static_cast<double>(warm->sim_time_ns) * 1e-9;
    EXPECT_FLOAT_EQ(warm->vehicles[0].speed, 10.0f);
    EXPECT_NEAR(warm->vehicles[0].position[0], 50.0 + 10.0 * t, 1e-6);
    EXPECT_FLOAT_EQ(warm->vehicles[1].speed, 0.0f);
    EXPECT_FLOAT_EQ(warm->vehicles[1].controls.throttle, 0.0f);
    // From sim time 0 the physics, with the driver's controls: the scripted car pulls away.
    EXPECT_TRUE(eventually(
        [&] {
          d.send(sim::ControlsMsg{1, {1.0f, 0.0f, 0.0f, false, false}, 0, 0});
          const auto s = w.last_state();
          return s && s->sim_time_ns > 500'000'000 && s->vehicles[1].speed > 0.5f;
        },
        5s));
    server.signal(SIGTERM);
    EXPECT_TRUE(server.wait(5s));
    w.close();
    d.close();
  }
  work.reset();
  io.stop();
  io_thread.join();
}

TEST(SimServerIT, ClientThatDoesNotReadIsDroppedOthersKeepStreaming) {
  // 100 cars make 16 KB State frames; a client with a tiny receive buffer that never reads
  // fills the kernel buffers within a second or two, then the server's queue of 20 frames.
  const auto dir =
      std::filesystem::temp_directory_path() / ("simserver-it-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto file = (dir / "hundred.json").string();
  {
    std::ofstream out(file);
    out << R"({"name":"hundred","map":{"type":"straight","lanes":4,"oncoming_lanes":0,)"
        << R"("length":1200},"origin":{"lat":41.1,"lon":29.0,"alt":0},"vehicles":[)";
    for (int i = 0; i < 100; ++i) {
      out << (i ? "," : "") << R"({"id":"v)" << i << R"(","station_id":)" << 1000 + i
          << R"(,"spawn":{"lane":)" << i % 4 << R"(,"s":)" << 20 + i * 10
          << R"(},"driver":"human"})";
    }
    out << "]}";
  }
  const auto port = free_port();
  const auto log = (dir / "server.log").string();
  ServerProcess server({"--scenario", file, "--port", std::to_string(port), "--bind", "127.0.0.1",
                        "--queue", "20", "--log-level", "warn"},
                       log);
  ASSERT_TRUE(server.started());

  asio::io_context io;
  auto work = asio::make_work_guard(io);
  std::thread io_thread([&] { io.run(); });
  {
    Client w(io, port);
    ASSERT_TRUE(w.connected());
    w.send(sim::Hello{"reader"});
    w.send(sim::Attach{sim::Role::kWatcher, 0});
    // The stalled client: a raw blocking socket with a small receive buffer, never read.
    asio::io_context io2;
    tcp::socket stalled(io2);
    stalled.open(tcp::v4());
    stalled.set_option(asio::socket_base::receive_buffer_size(4096));
    stalled.connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), port));
    auto hello = sim::encode(sim::Hello{"stalled"});
    auto attach = sim::encode(sim::Attach{sim::Role::kWatcher, 0});
    hello.insert(hello.end(), attach.begin(), attach.end());
    asio::write(stalled, asio::buffer(hello));

    // The server closes the stalled connection (and says so); reading it then drains the
    // buffered frames and ends in EOF.
    const auto said = [&] {
      std::ifstream in(log);
      const std::string text{std::istreambuf_iterator<char>(in), {}};
      return text.find("send queue full") != std::string::npos;
    };
    ASSERT_TRUE(eventually(said, 30s)) << "the server never dropped the client that does not read";
    std::size_t drained = 0;
    boost::system::error_code ec;
    std::array<std::uint8_t, 65536> buf;
    stalled.non_blocking(false);
    while (!ec)
      drained += stalled.read_some(asio::buffer(buf), ec);
    EXPECT_EQ(ec, asio::error::eof) << ec.message();
    EXPECT_LT(drained, 200u * 16'500) << "the server kept sending to a client that did not read";

    const auto before = w.states();
    EXPECT_TRUE(eventually([&] { return w.states() > before + 15; }, 5s))
        << "the reading client's stream stopped";
    EXPECT_FALSE(w.eof());
    w.close();
  }
  server.signal(SIGTERM);
  EXPECT_EQ(server.wait(5s), std::optional<int>(0));
  work.reset();
  io.stop();
  io_thread.join();
  std::filesystem::remove_all(dir);
}

TEST(SimServerIT, BadScenarioExitsWithTwoBeforeListening) {
  const auto port = free_port();
  ServerProcess server(
      {"--scenario", "sim-server/tests/scenarios/bad-lane.json", "--port", std::to_string(port)});
  ASSERT_TRUE(server.started());
  const auto rc = server.wait(5s);
  ASSERT_TRUE(rc);
  EXPECT_EQ(*rc, 2);
  asio::io_context io;
  tcp::socket s(io);
  boost::system::error_code ec;
  s.connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), port), ec);
  EXPECT_TRUE(ec) << "something listens on the port";
}

TEST(SimServerIT, RunStopsAfterItsDurationAndSaysTheScenarioFinished) {
  // In real time, not --fast: a fast run of a scenario without scripted drivers starts stepping
  // at once and may be over (3000 steps: ~0.2 s) before the watcher has connected (CI, loaded).
  const auto port = free_port();
  ServerProcess server({"--scenario", "sim-server/tests/scenarios/three-cars.json", "--port",
                        std::to_string(port), "--bind", "127.0.0.1", "--duration", "1",
                        "--log-level", "warn"});
  ASSERT_TRUE(server.started());
  asio::io_context io;
  auto work = asio::make_work_guard(io);
  std::thread io_thread([&] { io.run(); });
  // Joined however the checks below end (a failed ASSERT returns early).
  struct Join {
    std::function<void()> fn;
    ~Join() { fn(); }
  } join{[&] {
    work.reset();
    io.stop();
    io_thread.join();
  }};
  // A watcher that reads the stream to the end: the end of the scenario is told apart from a
  // server that stops (SIGTERM above: kShutdown) by the reason, not by the text.
  Client w(io, port);
  ASSERT_TRUE(w.connected());
  w.send(sim::Hello{"watcher"});
  w.send(sim::Attach{sim::Role::kWatcher, 0});
  const auto rc = server.wait(20s);
  ASSERT_TRUE(rc) << "1 s of sim time in real time should end well within 20 s";
  EXPECT_EQ(*rc, 0);
  ASSERT_TRUE(eventually([&] { return w.eof(); }, 2s));
  ASSERT_TRUE(w.find<sim::Closing>());
  EXPECT_EQ(w.find<sim::Closing>()->reason, sim::CloseReason::kScenarioFinished);
  w.close();
}

TEST(SimServerIT, SignalStatesFollowThePlanOnTheWorldClock) {
  // The shipped four-way junction's lights (issue 34), a short plan on a pinned clock:
  // groups 1+3 green 2 s, amber 1 s, all-red 0.5 s, red+amber 0.5 s for 2+4, their green 2 s,
  // ...: an 8 s cycle from 12:00:00Z. Worked out by hand, ms from the start (the 1 s warm-up
  // begins at 7 s into a cycle, all-red): 1+3 red+amber at -500, green at 0, amber at 2000,
  // red at 3000; 2+4 red+amber at 3500, green at 4000.
  const auto dir =
      std::filesystem::temp_directory_path() / ("simserver-it-sig-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto file = (dir / "lights.json").string();
  {
    std::ofstream out(file);
    out << R"({"name":"lights","map":{"type":"opendrive","file":")"
        << std::filesystem::absolute("scenarios/maps/four_way_junction.xodr").string()
        << R"("},"origin":{"lat":48.137,"lon":11.575},"start_time":"2026-11-27T12:00:00Z",)"
        << R"("warmup_s":1,"signals":[{"junction":"100","amber_s":1,"all_red_s":0.5,)"
        << R"("red_amber_s":0.5,"phases":[{"green":[1,3],"duration_s":2},)"
        << R"({"green":[2,4],"duration_s":2}]}],)"
        << R"("vehicles":[{"id":"h","station_id":1,"spawn":{"road":"1","lane":1,"s":50},)"
        << R"("driver":"human"}]})";
  }
  const auto port = free_port();
  ServerProcess server({"--scenario", file, "--port", std::to_string(port), "--bind", "127.0.0.1",
                        "--duration", "5", "--log-level", "warn"});
  ASSERT_TRUE(server.started());
  asio::io_context io;
  auto work = asio::make_work_guard(io);
  std::thread io_thread([&] { io.run(); });
  struct Join {
    std::function<void()> fn;
    ~Join() { fn(); }
  } join{[&] {
    work.reset();
    io.stop();
    io_thread.join();
    std::filesystem::remove_all(dir);
  }};
  Client w(io, port);
  ASSERT_TRUE(w.connected());
  w.send(sim::Hello{"watcher"});
  w.send(sim::Attach{sim::Role::kWatcher, 0});
  const auto rc = server.wait(30s);
  ASSERT_TRUE(rc) << "6 s of sim time in real time should end well within 30 s";
  EXPECT_EQ(*rc, 0);
  ASSERT_TRUE(eventually([&] { return w.eof(); }, 2s));

  const auto msgs = w.others();
  ASSERT_GE(msgs.size(), 2u);
  const auto* welcome = std::get_if<sim::Welcome>(&msgs[0]);
  ASSERT_NE(welcome, nullptr);
  const std::int64_t t0 = 1'795'780'800'000;  // 2026-11-27T12:00:00Z
  EXPECT_EQ(welcome->world_start_ns, t0 * 1'000'000);
  // Right after Welcome: the lights as of the world's present (before the first step).
  ASSERT_TRUE(std::holds_alternative<sim::SignalStates>(msgs[1]));
  std::vector<sim::SignalStates> got;
  for (const auto& m : msgs)
    if (const auto* s = std::get_if<sim::SignalStates>(&m))
      got.push_back(*s);
  const auto after = w.signals_after();
  ASSERT_EQ(after.size(), got.size());
  using P = sim::MovementPhaseState;
  const P g = P::kProtectedMovementAllowed, r = P::kStopAndRemain, a = P::kProtectedClearance,
          ra = P::kPreMovement;
  struct Change {
    std::int64_t at_ms;
    P odd, even;  // groups 1 and 3, groups 2 and 4
  };
  const Change plan[] = {{-500, ra, r}, {0, g, r},     {2000, a, r},
                         {3000, r, r},  {3500, r, ra}, {4000, r, g}};
  std::size_t seen = 0;
  for (std::size_t i = 0; i < got.size(); ++i) {
    const auto& s = got[i];
    ASSERT_EQ(s.groups.size(), 4u);
    // Each comes after the State of its own step: world time = start + that step's sim time.
    if (i > 0 && after[i]) {
      EXPECT_EQ(s.world_time_ms, t0 + *after[i] / 1'000'000) << "message " << i;
    }
    if (i > 0) {
      EXPECT_LE(s.world_time_ms - got[i - 1].world_time_ms, 1000 + 10) << "message " << i;
    }
    for (const Change& c : plan) {
      if (std::llabs(s.world_time_ms - (t0 + c.at_ms)) > 10)
        continue;
      ++seen;
      EXPECT_EQ(s.groups[0].state, c.odd) << "at " << c.at_ms;
      EXPECT_EQ(s.groups[2].state, c.odd) << "at " << c.at_ms;
      EXPECT_EQ(s.groups[1].state, c.even) << "at " << c.at_ms;
      EXPECT_EQ(s.groups[3].state, c.even) << "at " << c.at_ms;
    }
    // Between the changes the states are those of the stretch the plan says.
    const std::int64_t t = s.world_time_ms - t0;
    if (t > 10 && t < 1990) {
      EXPECT_EQ(s.groups[0].state, g) << t;
      EXPECT_EQ(s.groups[0].next_change_ms, t0 + 2000) << t;
      EXPECT_EQ(s.groups[1].next_change_ms, t0 + 3500) << t;
    }
  }
  EXPECT_EQ(seen, std::size(plan)) << "every change of the plan, in the step it happens";
  w.close();
}

}  // namespace
}  // namespace tb::server
