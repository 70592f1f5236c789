// Integration: a real gpsd, fed NMEA over UDP by the test, read through GpsdPositionProvider.
// Starts its own gpsd on free ports and stops it again; about 4 s.

#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <set>

#include <fmt/format.h>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <boost/asio/steady_timer.hpp>

#include "common/clock/asio_runtime.hpp"
#include "its-station/facilities/gpsd_position_provider.hpp"
#include "its-station/facilities/gpsd_process.hpp"
#include "its-station/facilities/tests/nmea_feed.hpp"

namespace tb::its::facilities {
namespace {

using namespace std::chrono_literals;
namespace asio = boost::asio;

int free_port(int type) {
  int fd = ::socket(AF_INET, type, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
  socklen_t len = sizeof a;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
  ::close(fd);
  return ntohs(a.sin_port);
}

/// An epoch of a car driving north-east at 10 m/s from (48.1, 11.5): 1 m north and 1 m east
/// per step (8.99e-6° of latitude, 1.347e-5° of longitude at 48.1°).
struct Epoch {
  clock::WallTime time;
  double lat, lon;
  std::string datagram;
};

Epoch make_epoch(clock::WallTime t, int k) {
  const double lat = 48.1 + k * 8.99e-6;
  const double lon = 11.5 + k * 1.347e-5;
  auto e = testing::nmea_epoch(t, lat, lon, 10.0, 45.0);
  return {e.time, lat, lon, e.datagram};
}

class GpsdIt : public ::testing::Test {
 protected:
  void SetUp() override {
    opts.client_port = std::to_string(free_port(SOCK_STREAM));
    opts.nmea_bind = "127.0.0.1";
    opts.nmea_port = std::to_string(free_port(SOCK_DGRAM));
    opts.listen_any = false;
    auto p = GpsdProcess::start(opts);
    ASSERT_TRUE(p) << p.error();
    gpsd.emplace(std::move(*p));
  }

  /// Sends one epoch every 100 ms until @p stop says so.
  void feed(const std::function<bool()>& stop) {
    if (stop())
      return;
    auto e = make_epoch(clock::WallClock::now(), step++);
    sent[clock::to_unix_ns(e.time) / 1'000'000] = e;
    sent_at[clock::to_unix_ns(e.time) / 1'000'000] = clock::SteadyClock::now();
    udp.send_to(asio::buffer(e.datagram),
                asio::ip::udp::endpoint(asio::ip::make_address("127.0.0.1"),
                                        static_cast<unsigned short>(std::stoi(opts.nmea_port))));
    feeder.expires_after(100ms);
    feeder.async_wait([this, stop](const boost::system::error_code& ec) {
      if (!ec)
        feed(stop);
    });
  }

  GpsdProcess::Options opts;
  std::optional<GpsdProcess> gpsd;
  asio::io_context io;
  clock::AsioRuntime rt{io};
  asio::ip::udp::socket udp{io, asio::ip::udp::v4()};
  asio::steady_timer feeder{io};
  int step = 0;
  std::map<std::int64_t, Epoch> sent;
  std::map<std::int64_t, clock::SteadyTime> sent_at;
};

TEST_F(GpsdIt, FixesArriveWithTheSentPositionTimeAndConfidence) {
  GpsdPositionProvider provider(io, rt, {"127.0.0.1", opts.client_port});
  std::vector<PositionFix> fixes;
  std::vector<std::int64_t> lag_us;  // epoch sent → fix handed to the listeners
  provider.on_fix([&](const PositionFix& f) {
    fixes.push_back(f);
    const auto it = sent_at.find(clock::to_unix_ns(f.time) / 1'000'000);
    if (it != sent_at.end())
      lag_us.push_back(std::chrono::duration_cast<std::chrono::microseconds>(
                           clock::SteadyClock::now() - it->second)
                           .count());
    if (fixes.size() >= 15)
      io.stop();
  });
  provider.start();  // gpsd may still be starting: the provider retries
  feed([&] { return fixes.size() >= 15; });
  io.run_for(8s);
  ASSERT_GE(fixes.size(), 15u) << "reports " << provider.reports();
  EXPECT_TRUE(provider.connected());
  int with_altitude = 0;
  for (const auto& f : fixes) {
    const auto it = sent.find(clock::to_unix_ns(f.time) / 1'000'000);
    ASSERT_NE(it, sent.end()) << "fix time not one of the epochs sent";
    EXPECT_NEAR(f.latitude_deg, it->second.lat, 2e-7);
    EXPECT_NEAR(f.longitude_deg, it->second.lon, 2e-7);
    ASSERT_TRUE(f.speed_mps);
    EXPECT_NEAR(*f.speed_mps, 10.0, 0.01);  // 19.438 kn
    ASSERT_TRUE(f.heading_deg);
    EXPECT_NEAR(*f.heading_deg, 45.0, 1e-6);
    // gpsd reports the first epoch as 2-D and without error estimates, from the RMC alone,
    // until GGA and GSA of the cycle have told it more; the rest are complete 3-D fixes.
    if (!f.altitude_m)
      continue;
    ++with_altitude;
    EXPECT_NEAR(*f.altitude_m, 547.0, 1e-3);  // MSL 500 + geoid separation 47
    // gpsd: eph = HDOP × 19 m; the confidences follow from HDOP 0.9.
    ASSERT_TRUE(f.position_confidence);
    EXPECT_NEAR(f.position_confidence->semi_major_m, 17.1, 1e-6);
    ASSERT_TRUE(f.speed_confidence_mps);
    EXPECT_NEAR(*f.speed_confidence_mps, speed_confidence_95(0.9), 1e-6);
    ASSERT_TRUE(f.heading_confidence_deg);
    EXPECT_LT(*f.heading_confidence_deg, 1.0);
  }
  EXPECT_GE(with_altitude, 12);
  // Event-driven: a fix reaches the listeners as soon as gpsd reports it, well inside one
  // epoch (100 ms), not at a polling period.
  ASSERT_GE(lag_us.size(), 10u);
  std::sort(lag_us.begin(), lag_us.end());
  std::printf("epoch sent -> fix delivered: median %.2f ms, max %.2f ms over %zu fixes\n",
              lag_us[lag_us.size() / 2] / 1e3, lag_us.back() / 1e3, lag_us.size());
  EXPECT_LT(lag_us[lag_us.size() / 2], 50'000);
}

TEST_F(GpsdIt, LossOnGpsdExitAndReconnectWhenItReturns) {
  GpsdPositionProvider::Config cfg{"127.0.0.1", opts.client_port};
  cfg.first_retry = 100ms;
  GpsdPositionProvider provider(io, rt, cfg);
  std::vector<bool> availability;
  int fixes = 0;
  provider.on_availability([&](bool a) { availability.push_back(a); });
  provider.on_fix([&](const PositionFix&) { ++fixes; });
  provider.start();
  enum { kFirst, kAfterKill, kRestarted, kDone } phase = kFirst;
  feed([&] { return phase == kDone; });
  asio::steady_timer watchdog(io);
  std::function<void()> poll = [&] {
    if (phase == kFirst && fixes >= 5) {
      gpsd->stop();  // the connection breaks: a negative gps_read
      phase = kAfterKill;
    } else if (phase == kAfterKill && !availability.empty() && !availability.back()) {
      auto p = GpsdProcess::start(opts);
      ASSERT_TRUE(p) << p.error();
      gpsd.emplace(std::move(*p));
      fixes = 0;
      phase = kRestarted;
    } else if (phase == kRestarted && fixes >= 5) {
      phase = kDone;
      io.stop();
      return;
    }
    watchdog.expires_after(20ms);
    watchdog.async_wait([&](const boost::system::error_code& ec) {
      if (!ec)
        poll();
    });
  };
  poll();
  io.run_for(15s);
  EXPECT_EQ(phase, kDone);
  EXPECT_GE(provider.reconnects(), 1u);
  ASSERT_GE(availability.size(), 3u);
  EXPECT_EQ(availability[0], true);
  EXPECT_EQ(availability[1], false);
  EXPECT_EQ(availability[2], true);
}

TEST(GpsdItNoServer, MissingGpsdIsReportedAndRetried) {
  asio::io_context io;
  clock::AsioRuntime rt{io};
  GpsdPositionProvider provider(io, rt, {"127.0.0.1", std::to_string(free_port(SOCK_STREAM))});
  std::string error;
  EXPECT_FALSE(provider.start(&error));
  EXPECT_NE(error.find("cannot connect to gpsd"), std::string::npos) << error;
  io.run_for(300ms);  // retries in the background without blocking or crashing
  EXPECT_FALSE(provider.connected());
}

TEST(GpsdProcessIt, MissingExecutableIsAClearError) {
  GpsdProcess::Options o;
  o.executable = "no-such-gpsd-binary";
  auto p = GpsdProcess::start(o);
  ASSERT_FALSE(p);
  EXPECT_NE(p.error().find("no-such-gpsd-binary"), std::string::npos);
}

}  // namespace
}  // namespace tb::its::facilities
