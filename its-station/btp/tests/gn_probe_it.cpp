// The its-gn-probe program on the veth stand-in: one probe in each namespace, one sending, the
// other printing what it receives; and the program's exit codes for bad input.

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/clock/utc.hpp"
#include "its-station/geonet/tests/netns_fixture.hpp"

namespace tb::its {
namespace {

using json = nlohmann::json;
using VethPair = testing::VethPair;

std::string probe() {
  const char* bin = std::getenv("TESTBED_BIN");
  return std::string(bin ? bin : "build/bin") + "/its-gn-probe";
}

/// A program whose stdout is read line by line.
class Child {
 public:
  explicit Child(const std::string& cmd) : pipe_(::popen(cmd.c_str(), "r")) {}
  ~Child() {
    if (pipe_)
      ::pclose(pipe_);
  }
  /// The next line parsed as JSON, or null at the end of the output.
  json next() {
    char line[4096];
    if (!pipe_ || std::fgets(line, sizeof line, pipe_) == nullptr)
      return nullptr;
    return json::parse(line, nullptr, false);
  }
  /// Reads the rest of the output (so the child never dies of SIGPIPE), waits for the end and
  /// returns the exit status.
  int wait() {
    while (!next().is_null()) {
    }
    FILE* pipe = std::exchange(pipe_, nullptr);
    if (pipe == nullptr)
      return -1;
    const int status = ::pclose(pipe);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

 private:
  FILE* pipe_;
};

std::string in_ns(const testing::Netns& ns, const std::string& args) {
  return "ip netns exec " + ns.name() + " " + probe() + " " + args + " 2>/dev/null";
}

void expect_received(Child& rx, const std::string& type, int count, const std::string& source) {
  for (int i = 0; i < count; ++i) {
    const json j = rx.next();
    ASSERT_TRUE(j.is_object()) << "line " << i;
    EXPECT_EQ(j["event"], "rx");
    EXPECT_EQ(j["type"], type);
    EXPECT_EQ(j["seq"], i);
    EXPECT_EQ(j["port"], 2001);
    EXPECT_EQ(j["source"], source);
    EXPECT_NEAR(j["latitude"].get<double>(), 48.1501, 1e-7);
  }
  const json summary = rx.next();
  EXPECT_EQ(summary["event"], "summary");
  EXPECT_EQ(summary["received"], count);
  EXPECT_EQ(rx.wait(), 0);
}

TEST_F(VethPair, ProbeSendsShbAndTheOtherProbeReceivesIt) {
  Child rx{in_ns(*b_, "--receive-count 4 --duration-s 20 --position 48.15 -1.6")};
  const json ready = rx.next();
  ASSERT_EQ(ready["event"], "ready") << ready.dump();
  EXPECT_EQ(ready["interface"], "wlan0");

  Child tx{in_ns(*a_, "--send shb --count 4 --interval-ms 20 --position 48.1501 -1.6")};
  const json tx_ready = tx.next();
  ASSERT_EQ(tx_ready["event"], "ready");
  for (int i = 0; i < 4; ++i)
    EXPECT_EQ(tx.next()["confirm"], "accepted");
  EXPECT_EQ(tx.next()["event"], "summary");
  EXPECT_EQ(tx.wait(), 0);
  expect_received(rx, "SHB", 4, tx_ready["address"]);
}

TEST_F(VethPair, ProbeGeoBroadcastsAcrossTheLink) {
  Child rx{in_ns(*b_, "--receive-count 2 --duration-s 20 --position 48.15 -1.6")};
  ASSERT_EQ(rx.next()["event"], "ready");
  Child tx{in_ns(*a_,
                 "--send gbc --area 48.15 -1.6 300 --count 2 --interval-ms 20 "
                 "--position 48.1501 -1.6")};
  const json tx_ready = tx.next();
  EXPECT_EQ(tx.wait(), 0);
  expect_received(rx, "GBC circle", 2, tx_ready["address"]);
}

TEST_F(VethPair, ProbeSendsCamsAndNamesTheCamsItHears) {
  Child rx{in_ns(*b_, "--receive-count 3 --duration-s 20 --position 48.15 -1.6 --cam 88")};
  ASSERT_EQ(rx.next()["event"], "ready");
  Child tx{in_ns(*a_,
                 "--send shb --count 3 --interval-ms 20 --position 48.1501 -1.6 --speed 12.5 "
                 "--heading 271 --cam 77")};
  EXPECT_EQ(tx.wait(), 0);
  for (int i = 0; i < 3; ++i) {
    const json j = rx.next();
    ASSERT_TRUE(j.is_object()) << "line " << i;
    EXPECT_EQ(j["event"], "rx");
    EXPECT_EQ(j["cam_station_id"], 77) << j.dump();  // a CAM it decoded, of station 77
    EXPECT_GT(j["length"].get<int>(), 30);
  }
  EXPECT_EQ(rx.next()["event"], "summary");
  EXPECT_EQ(rx.wait(), 0);
  Child no_position{in_ns(*a_, "--send shb --cam 5")};
  EXPECT_EQ(no_position.wait(), 2);
}

TEST_F(VethPair, ProbeExitCodesNameTheProblem) {
  // No interface of that name in the namespace: 1, and the message names it.
  EXPECT_EQ(std::system(("ip netns exec " + a_->name() + " " + probe() +
                         " --interface wlan9 2>&1 | grep -q \"interface 'wlan9': no such\"")
                            .c_str()),
            0);
  Child missing{in_ns(*a_, "--interface wlan9")};
  EXPECT_EQ(missing.wait(), 1);
  Child no_area{in_ns(*a_, "--send gbc --position 48 -1")};
  EXPECT_EQ(no_area.wait(), 2);
  Child off_globe{in_ns(*a_, "--send shb --position 91 0")};
  EXPECT_EQ(off_globe.wait(), 2);
  // Nothing arrives: 3 once the time is up.
  Child lonely{in_ns(*a_, "--receive-count 1 --duration-s 0.2")};
  EXPECT_EQ(lonely.wait(), 3);
}

/// A GNSS receiver's NMEA for @p seconds in @p ns: an RMC every 100 ms to UDP 10110 (the
/// station contract's feed), in the background, of the host's UTC less @p days_back days (a
/// world whose start time is pinned in the past).
void feed_nmea(const testing::Netns& ns, int seconds, int days_back) {
  const std::string script = ::testing::TempDir() + "/rmc_feed.py";
  std::FILE* f = std::fopen(script.c_str(), "w");
  ASSERT_NE(f, nullptr);
  std::fputs(
      "import datetime, socket, sys, time\n"
      "s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)\n"
      "end = time.time() + float(sys.argv[1])\n"
      "while time.time() < end:\n"
      "    t = datetime.datetime.now(datetime.timezone.utc) - "
      "datetime.timedelta(days=int(sys.argv[2]))\n"
      "    body = 'GPRMC,%s.%02d,A,4809.006,N,00136.000,W,0.0,0.0,%s,,,A' % (\n"
      "        t.strftime('%H%M%S'), t.microsecond // 10000, t.strftime('%d%m%y'))\n"
      "    cs = 0\n"
      "    for c in body:\n"
      "        cs ^= ord(c)\n"
      "    s.sendto(('$%s*%02X\\r\\n' % (body, cs)).encode(), ('127.0.0.1', 10110))\n"
      "    time.sleep(0.1)\n",
      f);
  std::fclose(f);
  ASSERT_EQ(std::system(("ip -n " + ns.name() + " link set lo up").c_str()), 0);
  ASSERT_EQ(
      std::system(("ip netns exec " + ns.name() + " python3 " + script + " " +
                   std::to_string(seconds) + " " + std::to_string(days_back) + " >/dev/null 2>&1 &")
                      .c_str()),
      0);
}

// Signing (issue 31): two probes with the files its-pki export writes verify each other's CAMs,
// dated on the GNSS time of their NMEA, a year behind the host's clock (the PKI made --at that
// time: on the host's clock the certificates would not be valid yet... nor the packets fresh);
// an unsigned probe's CAMs are dropped.
TEST_F(VethPair, SignedProbesVerifyEachOtherAndDropTheUnsigned) {
  const std::string bin = std::getenv("TESTBED_BIN") ? std::getenv("TESTBED_BIN") : "build/bin";
  const std::string pki = ::testing::TempDir() + "/gn-probe-pki";
  constexpr int kDaysBack = 365;
  const std::string world =
      clock::format_utc(clock::WallClock::now() - std::chrono::hours{24 * kDaysBack});
  ASSERT_EQ(std::system(("rm -rf " + pki + " && " + bin + "/its-pki make --dir " + pki +
                         "/ca --at " + world + " --station 77 --station 88 >/dev/null && " + bin +
                         "/its-pki export --dir " + pki + "/ca --station 77 --out " + pki +
                         "/77 >/dev/null && " + bin + "/its-pki export --dir " + pki +
                         "/ca --station 88 --out " + pki + "/88 >/dev/null")
                            .c_str()),
            0);
  auto files = [&](int id) {
    const std::string d = pki + "/" + std::to_string(id);
    return " --at-cert " + d + "/at-" + std::to_string(id) + ".cert --at-key " + d + "/at-" +
           std::to_string(id) + ".pem --trust " + d + "/root.cert --aa " + d + "/aa.cert";
  };
  feed_nmea(*a_, 15, kDaysBack);
  feed_nmea(*b_, 15, kDaysBack);
  Child rx{
      in_ns(*b_, "--receive-count 3 --duration-s 12 --position 48.15 -1.6 --cam 88" + files(88))};
  ASSERT_EQ(rx.next()["event"], "ready");
  Child unsigned_tx{
      in_ns(*a_, "--send shb --count 3 --interval-ms 20 --position 48.1501 -1.6 --cam 55")};
  EXPECT_EQ(unsigned_tx.wait(), 0);
  Child tx{in_ns(
      *a_, "--send shb --count 3 --interval-ms 50 --position 48.1501 -1.6 --cam 77" + files(77))};
  EXPECT_EQ(tx.wait(), 0);
  for (int i = 0; i < 3; ++i) {
    const json j = rx.next();
    ASSERT_TRUE(j.is_object()) << "line " << i;
    ASSERT_EQ(j.value("event", ""), "rx") << j.dump();
    EXPECT_EQ(j.value("cam_station_id", -1), 77) << j.dump();  // never 55's: unsigned, dropped
  }
  const json summary = rx.next();
  ASSERT_TRUE(summary.is_object());
  EXPECT_EQ(summary.value("event", ""), "summary");
  EXPECT_EQ(summary.value(json::json_pointer("/security/verify/ok"), -1), 3) << summary.dump();
  EXPECT_EQ(rx.wait(), 0);
  // A missing certificate file is named, exit 2.
  EXPECT_EQ(
      std::system(("ip netns exec " + a_->name() + " " + probe() + " --cam 1 --at-cert " + pki +
                   "/none.cert --at-key x --trust y --aa z 2>&1 | grep -q "
                   "'none.cert: cannot open'")
                      .c_str()),
      0);
  Child bad{in_ns(*a_, "--cam 1 --at-cert " + pki + "/none.cert --at-key x --trust y --aa z")};
  EXPECT_EQ(bad.wait(), 2);
}

}  // namespace
}  // namespace tb::its
