#include <arpa/inet.h>
#include <linux/errqueue.h>
#include <netinet/in.h>
#include <poll.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <deque>
#include <map>
#include <optional>
#include <set>
#include <thread>

#include <gtest/gtest.h>

#include "common/can/cannelloni.hpp"
#include "common/clock/clock.hpp"
#include "common/scenario/loader.hpp"
#include "network-emulator/app/batch_io.hpp"
#include "network-emulator/app/batch_sender.hpp"
#include "network-emulator/app/emulator.hpp"
#include "network-emulator/app/tests/test_scenario.hpp"

namespace tb::emu {
namespace {

Destination v4(const char* ip, std::uint16_t port) {
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  ::inet_pton(AF_INET, ip, &a.sin_addr);
  return Destination::from(reinterpret_cast<const sockaddr*>(&a), sizeof a);
}

Destination v6(const char* ip, std::uint16_t port) {
  sockaddr_in6 a{};
  a.sin6_family = AF_INET6;
  a.sin6_port = htons(port);
  ::inet_pton(AF_INET6, ip, &a.sin6_addr);
  return Destination::from(reinterpret_cast<const sockaddr*>(&a), sizeof a);
}

std::vector<std::uint8_t> bytes(std::string_view s) {
  return {s.begin(), s.end()};
}

/// A kernel as far as a batch sender sees it. Datagrams to a refused destination draw an ICMP
/// error at once, as on loopback: it goes on the error queue and becomes the socket's pending
/// error, which fails the next datagram of the same call whatever its destination.
class FakeKernel final : public BatchSocketOps {
 public:
  struct Sent {
    Destination to;
    std::string payload;
  };
  std::vector<Sent> delivered;
  std::vector<std::size_t> call_sizes;  // datagrams offered per send_many
  std::set<std::uint16_t> refused_ports;
  std::map<std::uint16_t, int> own_error;  // port → errno that send returns for it
  int full_for = 0;                        // this many next datagrams find the buffer full
  std::deque<QueuedError> error_queue;
  int pending_error = 0;
  std::optional<Destination> connected_to;  // a connected socket: datagrams without an address

  int send_many(std::span<mmsghdr> msgs) override {
    call_sizes.push_back(msgs.size());
    for (std::size_t i = 0; i < msgs.size(); ++i) {
      const msghdr& h = msgs[i].msg_hdr;
      if ((h.msg_name == nullptr) != connected_to.has_value())
        return i == 0 ? -EDESTADDRREQ : static_cast<int>(i);  // as the kernel, near enough
      const Destination to =
          connected_to ? *connected_to
                       : Destination::from(static_cast<const sockaddr*>(h.msg_name), h.msg_namelen);
      const std::uint16_t port = ntohs(reinterpret_cast<const sockaddr_in&>(to.addr).sin_port);
      int err = std::exchange(pending_error, 0);
      if (!err && full_for > 0) {
        --full_for;
        err = EAGAIN;
      }
      if (!err && own_error.count(port))
        err = own_error[port];
      if (err)
        return i == 0 ? -err : static_cast<int>(i);
      delivered.push_back(
          {to, std::string(static_cast<const char*>(h.msg_iov[0].iov_base), h.msg_iov[0].iov_len)});
      if (refused_ports.count(port)) {
        error_queue.push_back({to, std::make_error_code(std::errc::connection_refused)});
        pending_error = ECONNREFUSED;
      }
    }
    return static_cast<int>(msgs.size());
  }
  std::optional<QueuedError> read_error() override {
    if (error_queue.empty())
      return std::nullopt;
    QueuedError e = error_queue.front();
    error_queue.pop_front();
    pending_error = error_queue.empty() ? 0 : ECONNREFUSED;  // as sock_dequeue_err_skb does
    return e;
  }
};

TEST(BatchSender, AConnectedSenderSendsWithoutAddressesAndPausesAGoneReceiver) {
  FakeKernel k;
  k.connected_to = v4("127.0.0.1", 20000);
  BatchSender b(k, 512, /*connected=*/true);
  const auto can = b.add_sink(v4("127.0.0.1", 20000));
  EXPECT_FALSE(b.send(can, bytes("one")));
  EXPECT_FALSE(b.send(can, bytes("two")));
  b.flush();
  ASSERT_EQ(k.delivered.size(), 2u);  // an address would have been refused (EDESTADDRREQ)
  EXPECT_EQ(k.delivered[1].payload, "two");
  EXPECT_EQ(b.stats().failed, 0u);
  k.refused_ports = {20000};
  EXPECT_FALSE(b.send(can, bytes("three")));
  b.flush();
  EXPECT_EQ(b.send(can, bytes("four")), std::errc::connection_refused);
}

TEST(BatchSender, QueuesUntilFlushThenSendsAllInOneCall) {
  FakeKernel k;
  BatchSender b(k);
  const auto gnss = b.add_sink(v4("127.0.0.1", 10110));
  const auto can = b.add_sink(v4("10.0.0.2", 20000));
  EXPECT_FALSE(b.send(gnss, bytes("$GPRMC")));
  EXPECT_FALSE(b.send(can, bytes("can")));
  EXPECT_FALSE(b.send(gnss, bytes("$GPGGA")));
  EXPECT_TRUE(k.delivered.empty());
  b.flush();
  ASSERT_EQ(k.call_sizes, std::vector<std::size_t>{3});
  ASSERT_EQ(k.delivered.size(), 3u);
  EXPECT_EQ(k.delivered[0].payload, "$GPRMC");
  EXPECT_EQ(k.delivered[0].to, v4("127.0.0.1", 10110));
  EXPECT_EQ(k.delivered[1].payload, "can");
  EXPECT_EQ(k.delivered[1].to, v4("10.0.0.2", 20000));
  EXPECT_EQ(k.delivered[2].payload, "$GPGGA");
  EXPECT_EQ(b.stats().sent, 3u);
  EXPECT_EQ(b.stats().calls, 1u);
  b.flush();  // nothing queued: no system call
  EXPECT_EQ(k.call_sizes.size(), 1u);
}

TEST(BatchSender, AFullBatchIsSentBeforeTheNextDatagram) {
  FakeKernel k;
  BatchSender b(k, 2);
  const auto s = b.add_sink(v4("127.0.0.1", 1));
  for (const char* d : {"a", "b", "c", "d", "e"})
    EXPECT_FALSE(b.send(s, bytes(d)));
  EXPECT_EQ(k.call_sizes, (std::vector<std::size_t>{2, 2}));
  b.flush();
  EXPECT_EQ(k.call_sizes, (std::vector<std::size_t>{2, 2, 1}));
  ASSERT_EQ(k.delivered.size(), 5u);
  EXPECT_EQ(k.delivered[4].payload, "e");
}

TEST(BatchSender, AFullSocketBufferDropsOneDatagramAndParksNothing) {
  FakeKernel k;
  BatchSender b(k);
  const auto s = b.add_sink(v4("127.0.0.1", 1));
  for (const char* d : {"a", "b", "c"})
    b.send(s, bytes(d));
  k.full_for = 1;
  b.flush();
  ASSERT_EQ(k.delivered.size(), 2u);
  EXPECT_EQ(k.delivered[0].payload, "b");
  EXPECT_EQ(b.stats().dropped, 1u);
  EXPECT_EQ(b.stats().sent, 2u);
  EXPECT_FALSE(b.send(s, bytes("d")));
}

TEST(BatchSender, AnIcmpErrorIsParkedOnEverySinkOfItsDestinationOnly) {
  FakeKernel k;
  k.refused_ports = {10111};
  BatchSender b(k);
  const auto gone_a = b.add_sink(v4("127.0.0.1", 10111));
  const auto gone_b = b.add_sink(v4("127.0.0.1", 10111));  // a second feed to the same place
  const auto alive = b.add_sink(v4("127.0.0.1", 10110));
  b.send(gone_a, bytes("1"));
  b.send(alive, bytes("2"));
  b.send(alive, bytes("3"));
  b.flush();
  // The refusal of "1" made the kernel fail "2"; the sender read the queue and sent it again.
  ASSERT_EQ(k.delivered.size(), 3u);
  EXPECT_EQ(k.delivered[1].payload, "2");
  EXPECT_EQ(b.stats().failed, 0u);
  EXPECT_EQ(b.stats().late_errors, 1u);
  EXPECT_TRUE(k.error_queue.empty());
  EXPECT_EQ(k.pending_error, 0);
  // The next send of each sink of the gone receiver reports the error, and sends nothing.
  EXPECT_EQ(b.send(gone_a, bytes("x")), std::errc::connection_refused);
  EXPECT_EQ(b.send(gone_b, bytes("y")), std::errc::connection_refused);
  EXPECT_FALSE(b.send(alive, bytes("4")));
  EXPECT_FALSE(b.empty());
  b.flush();
  ASSERT_EQ(k.delivered.size(), 4u);
  EXPECT_EQ(k.delivered[3].payload, "4");
  // Once reported, the error is gone: the next send tries again (the probe).
  EXPECT_FALSE(b.send(gone_a, bytes("probe")));
}

TEST(BatchSender, AnErrorOfTheDatagramsOwnIsParkedOnItsSink) {
  FakeKernel k;
  k.own_error[9] = ENETUNREACH;
  BatchSender b(k);
  const auto a = b.add_sink(v4("127.0.0.1", 8));
  const auto unreachable = b.add_sink(v4("192.0.2.1", 9));
  b.send(a, bytes("1"));
  b.send(unreachable, bytes("2"));
  b.send(a, bytes("3"));
  b.flush();
  ASSERT_EQ(k.delivered.size(), 2u);
  EXPECT_EQ(k.delivered[1].payload, "3");
  EXPECT_EQ(b.stats().failed, 1u);
  EXPECT_EQ(b.take_error(unreachable), std::errc::network_unreachable);
  EXPECT_FALSE(b.take_error(a));
}

TEST(BatchSender, AnErrorLeftPendingSinceTheLastBatchBlamesNoInnocentDatagram) {
  // An ICMP answer that arrived between two batches (a real network is slower than loopback):
  // the first datagram of the next batch fails with it.
  FakeKernel k;
  BatchSender b(k);
  const auto gone = b.add_sink(v4("10.0.0.9", 10110));
  const auto alive = b.add_sink(v4("10.0.0.2", 10110));
  k.error_queue.push_back(
      {v4("10.0.0.9", 10110), std::make_error_code(std::errc::host_unreachable)});
  k.pending_error = EHOSTUNREACH;
  b.send(alive, bytes("a"));
  b.flush();
  ASSERT_EQ(k.delivered.size(), 1u);
  EXPECT_FALSE(b.take_error(alive));
  EXPECT_EQ(b.take_error(gone), std::errc::host_unreachable);
}

TEST(BatchSender, DestinationsCompareByFamilyAddressAndPort) {
  auto a = v4("127.0.0.1", 5);
  auto b = v4("127.0.0.1", 5);
  reinterpret_cast<sockaddr_in&>(b.addr).sin_zero[3] = 7;  // padding does not count
  EXPECT_EQ(a, b);
  EXPECT_EQ(DestinationHash{}(a), DestinationHash{}(b));
  EXPECT_FALSE(a == v4("127.0.0.1", 6));
  EXPECT_FALSE(a == v4("127.0.0.2", 5));
  EXPECT_FALSE(a == v6("::1", 5));
  EXPECT_EQ(v6("::1", 5), v6("::1", 5));
  EXPECT_EQ(a.to_string(), "127.0.0.1:5");
  EXPECT_EQ(v6("::1", 5).to_string(), "[::1]:5");
}

/// An error-queue message as recvmsg(MSG_ERRQUEUE) fills it in.
struct ErrqueueMessage {
  sockaddr_storage name{};
  alignas(cmsghdr) std::array<char, 256> control{};
  msghdr msg{};

  ErrqueueMessage(const Destination& to, int level, int type, std::uint8_t origin, int err,
                  std::size_t data_len = sizeof(sock_extended_err)) {
    std::memcpy(&name, &to.addr, to.len);
    msg.msg_name = &name;
    msg.msg_namelen = to.len;
    msg.msg_control = control.data();
    msg.msg_controllen = CMSG_SPACE(data_len);
    cmsghdr* c = CMSG_FIRSTHDR(&msg);
    c->cmsg_level = level;
    c->cmsg_type = type;
    c->cmsg_len = CMSG_LEN(data_len);
    sock_extended_err ee{};
    ee.ee_errno = static_cast<std::uint32_t>(err);
    ee.ee_origin = origin;
    ee.ee_type = 3;  // ICMP destination unreachable
    ee.ee_code = 3;  // port unreachable
    std::memcpy(CMSG_DATA(c), &ee, std::min(data_len, sizeof ee));
  }
};

TEST(ErrorQueue, ParsesAnIcmpPortUnreachableWithItsDestination) {
  ErrqueueMessage m(v4("127.0.0.1", 10111), SOL_IP, IP_RECVERR, SO_EE_ORIGIN_ICMP, ECONNREFUSED);
  const auto e = parse_error_queue_message(m.msg);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->destination, v4("127.0.0.1", 10111));
  EXPECT_EQ(e->error, std::errc::connection_refused);
}

TEST(ErrorQueue, ParsesIcmp6AndLocalErrors) {
  ErrqueueMessage m6(v6("fd00::2", 20000), SOL_IPV6, IPV6_RECVERR, SO_EE_ORIGIN_ICMP6,
                     EHOSTUNREACH);
  const auto e6 = parse_error_queue_message(m6.msg);
  ASSERT_TRUE(e6);
  EXPECT_EQ(e6->destination, v6("fd00::2", 20000));
  EXPECT_EQ(e6->error, std::errc::host_unreachable);
  ErrqueueMessage local(v4("10.0.0.2", 1), SOL_IP, IP_RECVERR, SO_EE_ORIGIN_LOCAL, EMSGSIZE);
  ASSERT_TRUE(parse_error_queue_message(local.msg));
  EXPECT_EQ(parse_error_queue_message(local.msg)->error, std::errc::message_size);
}

TEST(ErrorQueue, IgnoresWhatIsNoErrorAboutADestination) {
  // A time stamp on the error queue.
  ErrqueueMessage stamp(v4("127.0.0.1", 1), SOL_IP, IP_RECVERR, SO_EE_ORIGIN_TIMESTAMPING, ENOMSG);
  EXPECT_FALSE(parse_error_queue_message(stamp.msg));
  // No error number.
  ErrqueueMessage zero(v4("127.0.0.1", 1), SOL_IP, IP_RECVERR, SO_EE_ORIGIN_ICMP, 0);
  EXPECT_FALSE(parse_error_queue_message(zero.msg));
  // Another control message.
  ErrqueueMessage other(v4("127.0.0.1", 1), SOL_IP, IP_TTL, SO_EE_ORIGIN_ICMP, ECONNREFUSED);
  EXPECT_FALSE(parse_error_queue_message(other.msg));
  // Cut short.
  ErrqueueMessage cut(v4("127.0.0.1", 1), SOL_IP, IP_RECVERR, SO_EE_ORIGIN_ICMP, ECONNREFUSED, 4);
  EXPECT_FALSE(parse_error_queue_message(cut.msg));
  // No destination.
  ErrqueueMessage anonymous(v4("127.0.0.1", 1), SOL_IP, IP_RECVERR, SO_EE_ORIGIN_ICMP,
                            ECONNREFUSED);
  anonymous.msg.msg_namelen = 0;
  EXPECT_FALSE(parse_error_queue_message(anonymous.msg));
}

TEST(BatchedCanBus, SendsCannelloniDatagramsWithASequencePerDatagram) {
  FakeKernel k;
  BatchSender b(k);
  BatchedCanBus bus(b, v4("127.0.0.1", 20000));
  std::vector<tb::can::CanFrame> frames(
      3, tb::can::make_frame(0x100, std::vector<std::uint8_t>(8, 1)));
  EXPECT_FALSE(bus.send(frames));
  // 200 frames of 13 bytes do not fit in one 1400-byte datagram.
  std::vector<tb::can::CanFrame> many(200, frames[0]);
  EXPECT_FALSE(bus.send(many));
  b.flush();
  ASSERT_EQ(k.delivered.size(), 3u);
  std::size_t total = 0;
  for (std::size_t i = 0; i < k.delivered.size(); ++i) {
    const auto& p = k.delivered[i].payload;
    EXPECT_LE(p.size(), 1400u);
    const auto packet =
        tb::can::decode_cannelloni({reinterpret_cast<const std::uint8_t*>(p.data()), p.size()});
    ASSERT_TRUE(packet);
    EXPECT_EQ(packet->sequence, i);
    total += packet->frames.size();
  }
  EXPECT_EQ(total, 203u);
}

TEST(BatchedCanBus, ReportsTheParkedErrorBeforeQueueingAnything) {
  FakeKernel k;
  k.refused_ports = {20000};
  BatchSender b(k);
  BatchedCanBus bus(b, v4("127.0.0.1", 20000));
  const std::vector<tb::can::CanFrame> frames(
      1, tb::can::make_frame(0x100, std::vector<std::uint8_t>{1, 2}));
  EXPECT_FALSE(bus.send(frames));
  b.flush();
  EXPECT_EQ(bus.send(frames), std::errc::connection_refused);
  EXPECT_TRUE(b.empty());
}

/// DESIGN.md: the CAN frames one state makes travel in one cannelloni datagram, and the
/// states of one tick arrive in one batch datagram; nothing waits for a later state.
TEST(BatchedEmulator, EachStateSendsAllItsCanFramesInOneCannelloniDatagram) {
  const auto scen = scenario::parse(testing::kTwoStations, "two.json");
  const auto dbc = *tb::can::Database::load(TESTBED_VEHICLE_DBC);
  FakeKernel k;
  BatchSender b(k);
  clock::ManualClock clock;
  trace::Tracer no_trace;
  Emulator emu(
      scen, dbc, default_stations(scen),
      [&](const StationEndpoints& e) {
        return StationIo{std::make_unique<BatchedDatagramSink>(b, v4("127.0.0.1", e.gnss_port)),
                         std::make_unique<BatchedCanBus>(b, v4("127.0.0.1", e.can_port))};
      },
      clock, no_trace);
  for (const std::int64_t ms : {0, 10}) {
    std::vector<wire::VehicleState> tick;
    for (const std::uint32_t id : {1001u, 1002u}) {
      wire::VehicleState s;
      s.station_id = id;
      s.tick = static_cast<std::uint64_t>(ms / 10);
      s.sim_time_ns = ms * 1'000'000;
      s.position = {10.0, -1.75, 0.0};
      tick.push_back(s);
    }
    ASSERT_TRUE(emu.handle_datagram(wire::encode_batch(tick)));
    b.flush();
    // Per station one cannelloni datagram holding every frame due: at 0 ms the five dynamics
    // messages and Lights (100 ms), at 10 ms the five dynamics messages.
    std::map<std::uint16_t, std::vector<tb::can::CanFrame>> by_port;
    std::size_t can_datagrams = 0;
    for (const auto& d : k.delivered) {
      const auto port = ntohs(reinterpret_cast<const sockaddr_in&>(d.to.addr).sin_port);
      if (port < 20000)
        continue;  // NMEA
      ++can_datagrams;
      const auto p = tb::can::decode_cannelloni(
          {reinterpret_cast<const std::uint8_t*>(d.payload.data()), d.payload.size()});
      ASSERT_TRUE(p);
      by_port[port] = p->frames;
    }
    EXPECT_EQ(can_datagrams, 2u) << ms;
    for (const std::uint16_t port : {20000, 20001}) {
      std::set<std::uint32_t> ids;
      for (const auto& f : by_port[port])
        ids.insert(f.id());
      const std::set<std::uint32_t> want =
          ms == 0 ? std::set<std::uint32_t>{0x100, 0x101, 0x120, 0x130, 0x140, 0x200}
                  : std::set<std::uint32_t>{0x100, 0x101, 0x120, 0x130, 0x140};
      EXPECT_EQ(ids, want) << "port " << port << " at " << ms << " ms";
    }
    k.delivered.clear();
  }
  EXPECT_EQ(emu.counters().states, 4u);
  EXPECT_EQ(emu.counters().can_frames_sent, 22u);
}

/// The emulator on batched sinks: a station whose receivers are gone is paused through the
/// error queue, the other gets everything, and the station resumes when its receivers return.
TEST(BatchedEmulator, AStationThatIsGoneIsPausedAndResumesThroughTheErrorQueue) {
  const auto scen = scenario::parse(testing::kTwoStations, "two.json");
  const auto dbc = *tb::can::Database::load(TESTBED_VEHICLE_DBC);
  auto stations = default_stations(scen);  // ports 10110 + i and 20000 + i
  FakeKernel k;
  k.refused_ports = {10111, 20001};  // station 1002
  BatchSender b(k);
  clock::ManualClock clock;
  trace::Tracer no_trace;
  Emulator emu(
      scen, dbc, stations,
      [&](const StationEndpoints& e) {
        return StationIo{std::make_unique<BatchedDatagramSink>(b, v4("127.0.0.1", e.gnss_port)),
                         std::make_unique<BatchedCanBus>(b, v4("127.0.0.1", e.can_port))};
      },
      clock, no_trace);
  std::int64_t ms = 0;
  auto run_for = [&](std::int64_t duration_ms) {
    for (const std::int64_t end = ms + duration_ms; ms < end; ms += 10) {
      for (const std::uint32_t id : {1001u, 1002u}) {
        wire::VehicleState s;
        s.station_id = id;
        s.tick = static_cast<std::uint64_t>(ms / 10);
        s.sim_time_ns = ms * 1'000'000;
        s.position = {10.0, -1.75, 0.0};
        emu.handle_datagram(wire::encode_batch({&s, 1}));
      }
      b.flush();  // as the program does after each receive batch
      clock.advance(std::chrono::milliseconds(10));
    }
  };
  auto count_to = [&](std::uint16_t port) {
    return std::count_if(k.delivered.begin(), k.delivered.end(), [&](const auto& d) {
      return ntohs(reinterpret_cast<const sockaddr_in&>(d.to.addr).sin_port) == port;
    });
  };
  run_for(500);
  EXPECT_EQ(emu.paused_stations(), 1u);
  EXPECT_EQ(count_to(10110), 5);   // station 1001's every epoch
  EXPECT_EQ(count_to(20000), 50);  // and every CAN datagram
  EXPECT_EQ(count_to(10111), 1);   // station 1002: the first epoch drew the refusal
  EXPECT_EQ(count_to(20001), 1);
  EXPECT_EQ(emu.counters().nmea_failed, 1u);  // reported by the next send, then paused
  EXPECT_EQ(emu.counters().can_failed, 5u);   // the 5 dynamics frames of that send

  k.refused_ports.clear();  // the receivers are back
  const auto before = count_to(20001);
  run_for(1000);
  EXPECT_EQ(emu.paused_stations(), 0u);
  EXPECT_GT(count_to(20001), before + 40);  // resumed after one probe interval
  EXPECT_EQ(b.stats().failed, 0u);          // no innocent datagram was blamed
}

/// The same on the real kernel: a loopback port that nobody listens on.
TEST(UdpBatchSocket, TheKernelsIcmpErrorReachesTheSinkOfThatPortOnly) {
  const int rx = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(::bind(rx, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
  socklen_t len = sizeof a;
  ::getsockname(rx, reinterpret_cast<sockaddr*>(&a), &len);
  const auto listening = Destination::from(reinterpret_cast<sockaddr*>(&a), len);
  // A port that was free a moment ago: nobody listens there.
  const int probe = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in p = a;
  p.sin_port = 0;
  ::bind(probe, reinterpret_cast<sockaddr*>(&p), sizeof p);
  len = sizeof p;
  ::getsockname(probe, reinterpret_cast<sockaddr*>(&p), &len);
  ::close(probe);
  const auto nobody = Destination::from(reinterpret_cast<sockaddr*>(&p), len);

  UdpBatchSocket socket(AF_INET, "");
  BatchSender b(socket);
  const auto good = b.add_sink(listening), gone = b.add_sink(nobody);
  for (int round = 0; round < 3; ++round) {
    b.send(gone, bytes("x"));
    b.send(good, bytes("y"));
    b.send(good, bytes("z"));
    b.flush();
  }
  // Wait for the six datagrams and the ICMP error with a deadline, not for a fixed time that a
  // loaded machine may miss: loopback delivers within microseconds when the CPU is ours.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  const auto left_ms = [&] {
    return static_cast<int>(std::max<std::int64_t>(
        0, std::chrono::duration_cast<std::chrono::milliseconds>(deadline -
                                                                 std::chrono::steady_clock::now())
               .count()));
  };
  char buf[16];
  int got = 0;
  while (got < 6) {
    if (::recv(rx, buf, sizeof buf, MSG_DONTWAIT) > 0) {
      ++got;
      continue;
    }
    pollfd pfd{rx, POLLIN, 0};
    if (left_ms() == 0 || ::poll(&pfd, 1, left_ms()) <= 0)
      break;
  }
  EXPECT_EQ(got, 6);  // every datagram to the listening port arrived
  std::error_code gone_error;
  while (!gone_error) {
    b.read_errors();
    gone_error = b.take_error(gone);
    if (gone_error || left_ms() == 0)
      break;
    // The error queue raises POLLERR on the sending socket when the ICMP error is in.
    pollfd pfd{socket.fd(), 0, 0};
    ::poll(&pfd, 1, std::min(left_ms(), 50));
  }
  EXPECT_EQ(gone_error, std::errc::connection_refused);
  EXPECT_FALSE(b.take_error(good));
  EXPECT_EQ(b.stats().failed, 0u);
  ::close(rx);
}

/// BatchSenders with a connected socket per receiver, on the real kernel: the feed whose
/// receiver is gone gets its error, the other socket's feed none.
TEST(BatchSenders, OnlyTheConnectedSocketWhoseReceiverIsGoneGetsTheError) {
  // A listening UDP port on ::1 and a free one on 127.0.0.1: two sockets (one per family).
  const int rx = ::socket(AF_INET6, SOCK_DGRAM, 0);
  sockaddr_in6 l{};
  l.sin6_family = AF_INET6;
  l.sin6_addr = in6addr_loopback;
  if (::bind(rx, reinterpret_cast<sockaddr*>(&l), sizeof l) != 0) {
    ::close(rx);
    GTEST_SKIP() << "no IPv6 loopback";
  }
  socklen_t len = sizeof l;
  ::getsockname(rx, reinterpret_cast<sockaddr*>(&l), &len);
  const int probe = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in p{};
  p.sin_family = AF_INET;
  p.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ::bind(probe, reinterpret_cast<sockaddr*>(&p), sizeof p);
  len = sizeof p;
  ::getsockname(probe, reinterpret_cast<sockaddr*>(&p), &len);
  ::close(probe);  // nobody listens there now

  BatchSenders senders;
  const auto gone_to = Destination::from(reinterpret_cast<sockaddr*>(&p), sizeof p);
  const auto good_to = Destination::from(reinterpret_cast<sockaddr*>(&l), sizeof l);
  BatchedDatagramSink gone(senders.get_connected("", gone_to), gone_to);
  BatchedDatagramSink good(senders.get_connected("", good_to), good_to);
  ASSERT_EQ(senders.sockets(), 2u);
  // The gone feed learns of its receiver on a later send, as with a connected socket; a
  // deadline, not a fixed wait, covers an ICMP answer that a busy machine delivers late.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  std::error_code gone_error, good_error;
  int rounds = 0;
  while (!gone_error && std::chrono::steady_clock::now() < deadline) {
    gone_error = gone.send(bytes("x"));
    good_error = good.send(bytes("y"));
    senders.flush();
    ++rounds;
    if (good_error)
      break;
  }
  EXPECT_EQ(gone_error, std::errc::connection_refused);
  EXPECT_FALSE(good_error);
  const BatchStats st = senders.stats();
  EXPECT_GE(st.late_errors, 1u);
  EXPECT_EQ(st.failed, 0u);
  // Every datagram to the listening port arrived.
  char buf[8];
  int got = 0;
  while (got < rounds) {
    pollfd pfd{rx, POLLIN, 0};
    if (::poll(&pfd, 1, 10'000) <= 0 || ::recv(rx, buf, sizeof buf, 0) <= 0)
      break;
    ++got;
  }
  EXPECT_EQ(got, rounds);
  ::close(rx);
}

}  // namespace
}  // namespace tb::emu
