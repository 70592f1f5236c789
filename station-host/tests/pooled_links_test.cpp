#include <cstring>
#include <vector>

#include <gtest/gtest.h>

#include "common/wire/pooled_delivery.hpp"
#include "station-host/link/pooled_links.hpp"

namespace tb::host {
namespace {

using namespace std::chrono_literals;
namespace link = its::link;

struct CapturingOutput final : FrameOutput {
  std::vector<std::vector<std::uint8_t>> frames;
  std::error_code fail;
  std::error_code send_frame(std::span<const std::uint8_t> f) override {
    if (fail)
      return fail;
    frames.emplace_back(f.begin(), f.end());
    return {};
  }
};

struct Heard {
  std::uint32_t station;
  link::MacAddress source;
  link::MacAddress destination;
  const std::uint8_t* payload;
  std::size_t size;
  clock::WallTime rx_time;
};

std::vector<std::uint8_t> ethernet(const link::MacAddress& dst, const link::MacAddress& src,
                                   std::uint16_t ethertype, std::vector<std::uint8_t> payload) {
  std::vector<std::uint8_t> f(dst.begin(), dst.end());
  f.insert(f.end(), src.begin(), src.end());
  f.push_back(static_cast<std::uint8_t>(ethertype >> 8));
  f.push_back(static_cast<std::uint8_t>(ethertype));
  f.insert(f.end(), payload.begin(), payload.end());
  return f;
}

class PooledLinksTest : public ::testing::Test {
 protected:
  void make(bool loop_back) {
    links = std::make_unique<PooledLinks>(output, clock, loop_back, [this] { ++flush_requests; });
    for (std::uint32_t id : {3001u, 3002u, 3003u}) {
      links->link(id).set_receive_handler([this, id](const link::ReceivedFrame& f) {
        heard.push_back(
            {id, f.source, f.destination, f.payload.data(), f.payload.size(), f.rx_time});
      });
    }
  }
  std::vector<std::uint32_t> receivers() const {
    std::vector<std::uint32_t> ids;
    for (const Heard& h : heard)
      ids.push_back(h.station);
    return ids;
  }

  clock::ManualClock clock;
  CapturingOutput output;
  std::unique_ptr<PooledLinks> links;
  std::vector<Heard> heard;
  int flush_requests = 0;
  const clock::WallTime rx = clock::from_unix_ns(1'700'000'000'123'456'789);
  const link::MacAddress full_station = pooled_station_mac(2001);
};

TEST(PooledStationMac, Is0200ThenTheStationIdBigEndian) {
  EXPECT_EQ(pooled_station_mac(0x0A0B0C0D), (link::MacAddress{0x02, 0x00, 0x0A, 0x0B, 0x0C, 0x0D}));
}

TEST_F(PooledLinksTest, EachStationSendsWithItsOwnMac) {
  make(false);
  EXPECT_EQ(links->link(3002).address(), pooled_station_mac(3002));
  const std::vector<std::uint8_t> payload{1, 2, 3};
  ASSERT_FALSE(links->link(3002).send(link::kBroadcastMac, 0x8947, payload));
  ASSERT_EQ(output.frames.size(), 1u);
  EXPECT_EQ(output.frames[0],
            ethernet(link::kBroadcastMac, pooled_station_mac(3002), 0x8947, payload));
  // Kernel forwarding off: the medium decides every link, nothing is looped back here.
  EXPECT_EQ(flush_requests, 0);
  links->flush();
  EXPECT_TRUE(heard.empty());
  output.fail = std::make_error_code(std::errc::no_buffer_space);
  EXPECT_EQ(links->link(3001).send(link::kBroadcastMac, 0x8947, payload), output.fail);
  EXPECT_EQ(links->counters().send_errors, 1u);
  EXPECT_EQ(links->link(3001).send(link::kBroadcastMac, 0x8947,
                                   std::vector<std::uint8_t>(link::kMaxPayload + 1)),
            std::make_error_code(std::errc::message_size));
}

TEST_F(PooledLinksTest, PlainFrameGoesToEveryOwnStationButItsSenderWithoutCopies) {
  make(false);
  const auto from_air = ethernet(link::kBroadcastMac, full_station, 0x8947, {9, 8, 7});
  links->on_frame(from_air, rx);
  EXPECT_EQ(receivers(), (std::vector<std::uint32_t>{3001, 3002, 3003}));
  for (const Heard& h : heard) {
    EXPECT_EQ(h.payload, from_air.data() + 14);  // the frame read, not a copy per receiver
    EXPECT_EQ(h.size, 3u);
    EXPECT_EQ(h.rx_time, rx);  // the kernel's receive time
    EXPECT_EQ(h.source, full_station);
  }
  heard.clear();
  links->on_frame(ethernet(link::kBroadcastMac, pooled_station_mac(3002), 0x8947, {1}), rx);
  EXPECT_EQ(receivers(), (std::vector<std::uint32_t>{3001, 3003}));
}

TEST_F(PooledLinksTest, UnicastGoesToItsStationOnly) {
  make(false);
  links->on_frame(ethernet(pooled_station_mac(3003), full_station, 0x8947, {1}), rx);
  EXPECT_EQ(receivers(), std::vector<std::uint32_t>{3003});
  heard.clear();
  links->on_frame(ethernet(pooled_station_mac(4444), full_station, 0x8947, {1}), rx);
  links->on_frame(ethernet(link::kBroadcastMac, full_station, 0x0800, {1}), rx);
  links->on_frame(std::vector<std::uint8_t>(13, 0xff), rx);
  EXPECT_TRUE(heard.empty());
  EXPECT_EQ(links->counters().not_for_us, 3u);
}

TEST_F(PooledLinksTest, PooledDeliveryGoesToExactlyTheListedOwnStations) {
  make(false);
  const auto inner = ethernet(link::kBroadcastMac, full_station, 0x8947, {5, 6, 7, 8});
  const std::vector<std::uint32_t> ids{3003, 9999, 3001};
  const auto outer = wire::build_pooled_delivery_frame(ids, inner);
  links->on_frame(outer, rx);
  EXPECT_EQ(receivers(), (std::vector<std::uint32_t>{3003, 3001}));
  for (const Heard& h : heard) {
    EXPECT_EQ(h.source, full_station);  // the inner frame's, not the outer's
    EXPECT_EQ(h.size, 4u);
    EXPECT_EQ(h.payload, outer.data() + outer.size() - 4);
    EXPECT_EQ(h.rx_time, rx);
  }
  EXPECT_EQ(links->counters().foreign_receivers, 1u);
  EXPECT_EQ(links->counters().pooled, 1u);
  // A TBPD from one of our own stations back to another (user forwarding) is delivered too.
  heard.clear();
  const auto own = ethernet(link::kBroadcastMac, pooled_station_mac(3002), 0x8947, {1});
  links->on_frame(wire::build_pooled_delivery_frame(std::vector<std::uint32_t>{3001}, own), rx);
  EXPECT_EQ(receivers(), std::vector<std::uint32_t>{3001});
}

TEST_F(PooledLinksTest, MalformedPooledDeliveryIsDroppedAndCounted) {
  make(false);
  const auto inner = ethernet(link::kBroadcastMac, full_station, 0x8947, {5});
  auto outer = wire::build_pooled_delivery_frame(std::vector<std::uint32_t>{3001, 3002}, inner);
  auto bad_magic = outer;
  bad_magic[14] = 'X';
  links->on_frame(bad_magic, rx);
  auto truncated = outer;
  truncated.resize(14 + 8 + 6);  // the count says 2 ids, 1.5 follow
  links->on_frame(truncated, rx);
  auto not_gn = wire::build_pooled_delivery_frame(
      std::vector<std::uint32_t>{3001}, ethernet(link::kBroadcastMac, full_station, 0x0800, {1}));
  links->on_frame(not_gn, rx);
  EXPECT_TRUE(heard.empty());
  EXPECT_EQ(links->counters().malformed_pooled, 3u);
}

TEST_F(PooledLinksTest, KernelForwardingLoopsOwnTransmissionsBackOutsideSend) {
  make(true);
  clock.advance(5ms);
  const std::vector<std::uint8_t> payload{4, 2};
  ASSERT_FALSE(links->link(3002).send(link::kBroadcastMac, 0x8947, payload));
  ASSERT_FALSE(links->link(3001).send(pooled_station_mac(3003), 0x8947, payload));
  EXPECT_TRUE(heard.empty());  // never from inside send()
  EXPECT_EQ(flush_requests, 1);
  // A station that answers while receiving: its frame waits for the next flush.
  links->link(3003).set_receive_handler([this](const link::ReceivedFrame& f) {
    heard.push_back({3003, f.source, f.destination, f.payload.data(), f.payload.size(), f.rx_time});
    if (f.source == pooled_station_mac(3002))
      (void)links->link(3003).send(link::kBroadcastMac, 0x8947, f.payload);
  });
  links->flush();
  EXPECT_EQ(receivers(), (std::vector<std::uint32_t>{3001, 3003, 3003}));
  EXPECT_EQ(heard[0].rx_time, clock.wall_now());
  EXPECT_EQ(heard[0].source, pooled_station_mac(3002));
  EXPECT_EQ(heard[2].source, pooled_station_mac(3001));
  EXPECT_EQ(heard[2].destination, pooled_station_mac(3003));
  EXPECT_EQ(flush_requests, 2);
  heard.clear();
  links->flush();
  EXPECT_EQ(receivers(), (std::vector<std::uint32_t>{3001, 3002}));
  EXPECT_EQ(links->counters().looped_back, 5u);
  EXPECT_EQ(output.frames.size(), 3u);
}

}  // namespace
}  // namespace tb::host
