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
  const auto da = wire::decode(sink.sent[0]);
  const auto db = wire::decode(sink.sent[1]);
  ASSERT_TRUE(da.has_value());
  ASSERT_TRUE(db.has_value());
  auto expect_a = a;
  expect_a.send_wall_ns = clock::to_unix_ns(clk.wall_now()) - 5000;
  EXPECT_EQ(*da, expect_a);
  EXPECT_EQ(db->send_wall_ns, clock::to_unix_ns(clk.wall_now()));
  EXPECT_EQ(db->station_id, 1002u);
  EXPECT_EQ(fwd.sent(), 2u);
}

TEST(StateForwarder, CountsFailuresAndTracesForwards) {
  clock::ManualClock clk;
  CaptureSink sink;
  const std::string path = ::testing::TempDir() + "/simclient_forward_trace.jsonl";
  std::remove(path.c_str());
  {
    trace::Tracer tracer(path, "sim-client");
    StateForwarder fwd(clk, sink, tracer);
    fwd.forward(sample(1001, 42));
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
  EXPECT_NE(t.find("\"tick\":42"), std::string::npos) << t;
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
  for (const auto& want : sent) {
    std::array<std::uint8_t, 512> buf{};
    const std::size_t n = rx.receive(asio::buffer(buf));
    ASSERT_EQ(n, wire::kVehicleStateSize);
    auto got = wire::decode(std::span<const std::uint8_t>(buf.data(), n));
    ASSERT_TRUE(got.has_value()) << to_string(got.error());
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

}  // namespace
}  // namespace tb::client
