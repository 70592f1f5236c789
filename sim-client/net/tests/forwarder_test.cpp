#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <vector>

#include <fmt/format.h>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>

#include "sim-client/net/forwarder.hpp"

namespace tb::client {
namespace {

class CaptureSink final : public DatagramSink {
 public:
  bool send(std::span<const std::uint8_t> d) override {
    if (fail)
      return false;
    sent.emplace_back(d.begin(), d.end());
    return true;
  }
  std::vector<std::vector<std::uint8_t>> sent;
  bool fail = false;
};

wire::VehicleState sample(std::uint32_t station, std::uint64_t tick) {
  wire::VehicleState s;
  s.station_id = station;
  s.tick = tick;
  s.sim_time_ns = static_cast<std::int64_t>(tick) * 10'000'000;
  s.step_wall_ns = 1'700'000'000'000'000'000 + s.sim_time_ns;
  s.position = {12.5, -3.25, 0.4};
  s.yaw = 0.3f;
  s.velocity = {10.0f, 1.0f, 0.0f};
  s.speed = 10.05f;
  s.controls.throttle = 0.4f;
  s.controls.steer = -0.1f;
  s.gear = 3;
  s.lights = wire::kLowBeam | wire::kIndicatorLeft;
  s.engine_rpm = 2100.0f;
  return s;
}

std::vector<wire::VehicleState> decoded(const std::vector<std::uint8_t>& datagram) {
  std::vector<wire::VehicleState> out;
  const auto n = wire::decode_batch(datagram, out);
  EXPECT_TRUE(n.has_value()) << wire::to_string(n.error());
  return out;
}

TEST(StateForwarder, StampsSendTimeAndDatagramsDecodeToTheStates) {
  clock::ManualClock clk;
  clk.advance(std::chrono::milliseconds(1234));
  CaptureSink sink;
  trace::Tracer off;
  StateForwarder fwd(clk, sink, off);
  const auto a = sample(1001, 7), b = sample(1002, 7);
  fwd.forward(a);
  clk.advance(std::chrono::microseconds(5));
  fwd.forward(b);
  ASSERT_EQ(sink.sent.size(), 2u);
  const auto da = decoded(sink.sent[0]);
  const auto db = decoded(sink.sent[1]);
  ASSERT_EQ(da.size(), 1u);
  ASSERT_EQ(db.size(), 1u);
  auto expect_a = a;
  expect_a.send_wall_ns = clock::to_unix_ns(clk.wall_now()) - 5000;
  EXPECT_EQ(da[0], expect_a);
  EXPECT_EQ(db[0].send_wall_ns, clock::to_unix_ns(clk.wall_now()));
  EXPECT_EQ(db[0].station_id, 1002u);
  EXPECT_EQ(fwd.sent(), 2u);
}

TEST(StateForwarder, ATicksStatesGoInAsFewDatagramsAsFitInOrder) {
  clock::ManualClock clk;
  CaptureSink sink;
  trace::Tracer off;
  StateForwarder fwd(clk, sink, off);
  std::vector<wire::VehicleState> tick;
  for (std::uint32_t i = 0; i < 20; ++i)
    tick.push_back(sample(2001 + i, 99));
  fwd.forward_tick(tick);
  // 9 states fit in 1472 bytes: 9 + 9 + 2, the last one not held back for a later tick.
  ASSERT_EQ(sink.sent.size(), 3u);
  std::vector<wire::VehicleState> all;
  for (const auto& d : sink.sent) {
    EXPECT_LE(d.size(), wire::kDefaultBatchDatagramSize);
    for (auto& s : decoded(d))
      all.push_back(s);
  }
  EXPECT_EQ(decoded(sink.sent[0]).size(), 9u);
  EXPECT_EQ(decoded(sink.sent[2]).size(), 2u);
  ASSERT_EQ(all.size(), tick.size());
  for (std::size_t i = 0; i < tick.size(); ++i) {
    auto want = tick[i];
    want.send_wall_ns = clock::to_unix_ns(clk.wall_now());
    EXPECT_EQ(all[i], want) << i;
  }
  EXPECT_EQ(fwd.sent(), 20u);
  EXPECT_EQ(fwd.datagrams(), 3u);
  // A smaller datagram limit makes more, smaller datagrams; one state always fits.
  sink.sent.clear();
  fwd.forward_tick(tick, wire::batch_datagram_size(4));
  EXPECT_EQ(sink.sent.size(), 5u);
  sink.sent.clear();
  fwd.forward_tick(tick, 1);
  EXPECT_EQ(sink.sent.size(), 20u);
}

TEST(StateForwarder, CountsFailuresAndTracesForwards) {
  clock::ManualClock clk;
  CaptureSink sink;
  const std::string path = ::testing::TempDir() + "/simclient_forward_trace.jsonl";
  std::remove(path.c_str());
  {
    trace::Tracer tracer(path, "sim-client");
    StateForwarder fwd(clk, sink, tracer);
    auto warm = sample(1001, 42);
    warm.sim_time_ns = -1'230'000'000;  // a warm-up state
    fwd.forward(warm);
    sink.fail = true;
    fwd.forward(sample(1001, 43));
    EXPECT_EQ(fwd.sent(), 1u);
    EXPECT_EQ(fwd.failed(), 1u);
  }
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  const std::string t = text.str();
  EXPECT_NE(t.find("\"ev\":\"client.forward\""), std::string::npos) << t;
  EXPECT_NE(t.find("\"station\":1001"), std::string::npos) << t;
  EXPECT_NE(t.find("\"tick\":42,\"sim_ns\":-1230000000"), std::string::npos) << t;
  EXPECT_EQ(t.find("\"tick\":43"), std::string::npos) << t;  // not sent, not traced
  const auto s = sample(1001, 42);
  EXPECT_NE(t.find(fmt::format("\"x\":{},\"y\":{},\"v\":{}", s.position[0], s.position[1],
                               static_cast<double>(s.speed))),
            std::string::npos)
      << t;
}

TEST(UdpSink, DatagramsReachAReceiverAndDecode) {
  namespace asio = boost::asio;
  asio::io_context io;
  asio::ip::udp::socket rx(io, asio::ip::udp::endpoint(asio::ip::address_v4::loopback(), 0));
  const auto port = rx.local_endpoint().port();
  UdpSink sink(io, "127.0.0.1:" + std::to_string(port));
  clock::SystemClock clk;
  trace::Tracer off;
  StateForwarder fwd(clk, sink, off);
  std::vector<wire::VehicleState> sent;
  for (std::uint64_t tick = 1; tick <= 20; ++tick) {
    for (std::uint32_t st : {1001u, 1002u}) {
      sent.push_back(sample(st, tick));
      const auto before = clock::to_unix_ns(clk.wall_now());
      fwd.forward(sent.back());
      sent.back().send_wall_ns = before;  // checked separately below
    }
  }
  std::vector<wire::VehicleState> states;
  for (const auto& want : sent) {
    std::array<std::uint8_t, 2048> buf{};
    const std::size_t n = rx.receive(asio::buffer(buf));
    ASSERT_EQ(n, wire::batch_datagram_size(1));
    const auto count = wire::decode_batch(std::span<const std::uint8_t>(buf.data(), n), states);
    ASSERT_TRUE(count.has_value()) << to_string(count.error());
    ASSERT_EQ(states.size(), 1u);
    auto got = &states[0];
    EXPECT_GE(got->send_wall_ns, want.send_wall_ns);
    EXPECT_LT(got->send_wall_ns - want.send_wall_ns, 1'000'000'000);
    got->send_wall_ns = want.send_wall_ns;
    EXPECT_EQ(*got, want);
  }
}

TEST(SplitHostPort, FormsAndErrors) {
  EXPECT_EQ(split_host_port("127.0.0.1:4701", 4700),
            std::make_pair(std::string("127.0.0.1"), std::uint16_t{4701}));
  EXPECT_EQ(split_host_port("emulator", 4700).second, 4700);
  EXPECT_EQ(split_host_port("[::1]:9", 4700), std::make_pair(std::string("::1"), std::uint16_t{9}));
  EXPECT_THROW(split_host_port("host:0", 4700), std::invalid_argument);
  EXPECT_THROW(split_host_port("host:70000", 4700), std::invalid_argument);
  EXPECT_THROW(split_host_port("host:12a", 4700), std::invalid_argument);
  EXPECT_THROW(split_host_port(":4700", 4700), std::invalid_argument);
  boost::asio::io_context io;
  EXPECT_THROW(UdpSink(io, "no-such-host.invalid:1"), std::runtime_error);
}

TEST(SignalFeedAddress, IsTheStatePortPlusOne) {
  EXPECT_EQ(signal_feed_address("127.0.0.1:4700"), "127.0.0.1:4701");
  EXPECT_EQ(signal_feed_address("emulator"), "emulator:4701");  // the default state port
  EXPECT_EQ(signal_feed_address("10.0.0.5:5000"), "10.0.0.5:5001");
  EXPECT_EQ(signal_feed_address("[::1]:4700"), "[::1]:4701");
  EXPECT_THROW(signal_feed_address("h:65535"), std::invalid_argument);
  EXPECT_THROW(signal_feed_address("h:x"), std::invalid_argument);
}

TEST(SignalForwarder, CountsFailuresAndOversizedMessages) {
  CaptureSink sink;
  trace::Tracer off;
  SignalForwarder fwd(sink, off);
  wire::sim::SignalStates states{10, {{1, 1, wire::sim::MovementPhaseState::kStopAndRemain, 0, 0}}};
  sink.fail = true;
  fwd.forward(states);
  EXPECT_EQ(fwd.failed(), 1u);
  EXPECT_EQ(fwd.sent(), 0u);
  sink.fail = false;
  fwd.forward(states);
  EXPECT_EQ(fwd.sent(), 1u);
  ASSERT_EQ(sink.sent.size(), 1u);
  // More groups than a datagram holds: dropped, never cut.
  states.groups.clear();
  for (int i = 0; i < 4000; ++i)
    states.groups.push_back({static_cast<std::uint16_t>(i / 254),
                             static_cast<std::uint8_t>(1 + i % 254),
                             wire::sim::MovementPhaseState::kStopAndRemain, 0, 0});
  fwd.forward(states);
  EXPECT_EQ(fwd.too_large(), 1u);
  EXPECT_EQ(sink.sent.size(), 1u);
}

}  // namespace
}  // namespace tb::client
