#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <iterator>

#include <linux/if_packet.h>

#include <boost/asio/io_context.hpp>

#include "its-station/link/capturing_link.hpp"
#include "its-station/link/packet_socket_link.hpp"
#include "its-station/link/pcap_reader.hpp"
#include "its-station/link/pcap_writer.hpp"
#include "its-station/link/test_link.hpp"

namespace tb::its::link {
namespace {

TEST(MacAddress, PrintsLowerCaseColonSeparated) {
  EXPECT_EQ(to_string(MacAddress{0x02, 0x00, 0x5e, 0xAB, 0xcd, 0x0f}), "02:00:5e:ab:cd:0f");
  EXPECT_EQ(to_string(kBroadcastMac), "ff:ff:ff:ff:ff:ff");
}

TEST(TestLink, RecordsSentFramesAndDeliversInjectedOnes) {
  TestLink link{{2, 0, 0, 0, 0, 1}};
  const std::uint8_t data[] = {1, 2, 3};
  EXPECT_FALSE(link.send(kBroadcastMac, kEtherTypeGeoNetworking, data));
  ASSERT_EQ(link.sent().size(), 1u);
  EXPECT_EQ(link.sent()[0].destination, kBroadcastMac);
  EXPECT_EQ(link.sent()[0].payload, (std::vector<std::uint8_t>{1, 2, 3}));

  ReceivedFrame got;
  std::vector<std::uint8_t> got_payload;
  link.set_receive_handler([&](const ReceivedFrame& f) {
    got = f;
    got_payload.assign(f.payload.begin(), f.payload.end());
  });
  const clock::WallTime t{std::chrono::seconds{42}};
  link.inject({2, 0, 0, 0, 0, 9}, kBroadcastMac, kEtherTypeGeoNetworking, data, t);
  EXPECT_EQ(got.source, (MacAddress{2, 0, 0, 0, 0, 9}));
  EXPECT_EQ(got.rx_time, t);
  EXPECT_EQ(got_payload, (std::vector<std::uint8_t>{1, 2, 3}));
}

TEST(TestLink, RejectsFramesLargerThanTheMtuAndReportsInjectedFailures) {
  TestLink link{{2, 0, 0, 0, 0, 1}};
  std::vector<std::uint8_t> big(kMaxPayload + 1);
  EXPECT_EQ(link.send(kBroadcastMac, kEtherTypeGeoNetworking, big),
            std::make_error_code(std::errc::message_size));
  link.fail_sends_with(std::make_error_code(std::errc::network_down));
  EXPECT_EQ(link.send(kBroadcastMac, kEtherTypeGeoNetworking, std::span<const std::uint8_t>{}),
            std::make_error_code(std::errc::network_down));
  EXPECT_TRUE(link.sent().empty());
}

TEST(PacketSocketLink, MissingInterfaceGivesAnErrorNamingIt) {
  boost::asio::io_context io;
  auto link = PacketSocketLink::open(io, "gnnosuch0");
  ASSERT_FALSE(link);
  EXPECT_EQ(link.error().kind, OpenErrorKind::kNoSuchInterface);
  EXPECT_NE(link.error().message().find("'gnnosuch0'"), std::string::npos);
  EXPECT_NE(link.error().message().find("no such interface"), std::string::npos);
}

TEST(PacketSocketLink, OverlongInterfaceNameIsRejectedBeforeAnySyscall) {
  boost::asio::io_context io;
  auto link = PacketSocketLink::open(io, "an-interface-name-too-long");
  ASSERT_FALSE(link);
  EXPECT_EQ(link.error().kind, OpenErrorKind::kNoSuchInterface);
  EXPECT_NE(link.error().message().find("Invalid argument"), std::string::npos);
}

TEST(PacketSocketLink, ClassifiesEachReceivedFrame) {
  constexpr std::size_t kCapacity = 14 + kMaxPayload + 1;
  EXPECT_EQ(classify_received(PACKET_HOST, 100, false, kCapacity), RxVerdict::kDeliver);
  EXPECT_EQ(classify_received(PACKET_BROADCAST, 14 + kMaxPayload, false, kCapacity),
            RxVerdict::kDeliver);
  EXPECT_EQ(classify_received(PACKET_OUTGOING, 100, false, kCapacity), RxVerdict::kOutgoing);
  EXPECT_EQ(classify_received(PACKET_OTHERHOST, 100, false, kCapacity), RxVerdict::kOtherHost);
  // A frame that fills the spare byte, or that the kernel cut, is larger than an MTU.
  EXPECT_EQ(classify_received(PACKET_BROADCAST, kCapacity, false, kCapacity),
            RxVerdict::kTruncated);
  EXPECT_EQ(classify_received(PACKET_BROADCAST, 9000, true, kCapacity), RxVerdict::kTruncated);
}

TEST(PacketSocketLink, ParsesTheEthernetHeaderAndRefusesAShorterFrame) {
  const std::vector<std::uint8_t> bytes = {0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0x02, 0x00,
                                           0x00, 0x00, 0x03, 0xe9, 0x89, 0x47, 0x11, 0x22};
  const clock::WallTime t{std::chrono::seconds{1'700'000'000}};
  const auto f = parse_ethernet(bytes, t);
  ASSERT_TRUE(f);
  EXPECT_EQ(f->destination, kBroadcastMac);
  EXPECT_EQ(f->source, (MacAddress{0x02, 0x00, 0x00, 0x00, 0x03, 0xe9}));
  EXPECT_EQ(f->ethertype, kEtherTypeGeoNetworking);
  ASSERT_EQ(f->payload.size(), 2u);
  EXPECT_EQ(f->payload.data(), bytes.data() + 14) << "the payload points into the buffer";
  EXPECT_EQ(f->rx_time, t);
  EXPECT_FALSE(parse_ethernet(std::span(bytes).first(13), t));
  EXPECT_TRUE(parse_ethernet(std::span(bytes).first(14), t));
}

}  // namespace
}  // namespace tb::its::link

namespace tb::its::link {
namespace {

std::vector<std::uint8_t> read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(PcapWriter, WritesTheClassicHeaderAndOneRecordPerFrame) {
  const std::string path = ::testing::TempDir() + "/gn_link_test.pcap";
  {
    auto w = PcapWriter::create(path);
    ASSERT_TRUE(w) << w.error();
    const std::uint8_t payload[] = {0x11, 0x22};
    // 1.5 s after the Unix epoch.
    ASSERT_TRUE(w->write(clock::WallTime{std::chrono::milliseconds{1500}}, kBroadcastMac,
                         {2, 0, 0, 0, 0, 1}, kEtherTypeGeoNetworking, payload));
    ASSERT_TRUE(w->flush());
  }
  const std::vector<std::uint8_t> expected = {
      0xd4, 0xc3, 0xb2, 0xa1, 0x02, 0x00, 0x04, 0x00,  // magic, version 2.4
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,  // zone, sigfigs
      0xff, 0xff, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00,  // snaplen 65535, Ethernet
      0x01, 0x00, 0x00, 0x00, 0x20, 0xa1, 0x07, 0x00,  // 1 s, 500000 µs
      0x10, 0x00, 0x00, 0x00, 0x10, 0x00, 0x00, 0x00,  // 16 bytes captured, 16 on the wire
      0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0x02, 0x00, 0x00, 0x00, 0x00, 0x01,  // dst, src
      0x89, 0x47, 0x11, 0x22};                                                 // type, data
  EXPECT_EQ(read_file(path), expected);
  std::remove(path.c_str());
}

TEST(PcapReader, ReadsBackWhatTheWriterWrote) {
  const std::string path = ::testing::TempDir() + "/gn_reader_test.pcap";
  {
    auto w = PcapWriter::create(path);
    ASSERT_TRUE(w) << w.error();
    const std::uint8_t one[] = {0x11, 0x22};
    const std::uint8_t two[] = {0x33};
    ASSERT_TRUE(w->write(clock::WallTime{std::chrono::milliseconds{1500}}, kBroadcastMac,
                         {2, 0, 0, 0, 0, 1}, kEtherTypeGeoNetworking, one));
    ASSERT_TRUE(w->write(clock::WallTime{std::chrono::microseconds{2'000'007}}, {2, 0, 0, 0, 0, 9},
                         {2, 0, 0, 0, 0, 2}, 0x0800, two));
    ASSERT_TRUE(w->flush());
  }
  const auto frames = read_capture(path);
  ASSERT_TRUE(frames) << frames.error();
  ASSERT_EQ(frames->size(), 2u);
  EXPECT_EQ((*frames)[0].time, clock::WallTime{std::chrono::milliseconds{1500}});
  EXPECT_EQ((*frames)[0].destination, kBroadcastMac);
  EXPECT_EQ((*frames)[0].source, (MacAddress{2, 0, 0, 0, 0, 1}));
  EXPECT_EQ((*frames)[0].ethertype, kEtherTypeGeoNetworking);
  EXPECT_EQ((*frames)[0].payload, (std::vector<std::uint8_t>{0x11, 0x22}));
  EXPECT_EQ((*frames)[1].time, clock::WallTime{std::chrono::microseconds{2'000'007}});
  EXPECT_EQ((*frames)[1].ethertype, 0x0800);

  // A record cut short names where.
  auto bytes = read_file(path);
  bytes.pop_back();
  const auto cut = parse_capture(bytes);
  ASSERT_FALSE(cut);
  EXPECT_NE(cut.error().find("truncated at byte 56"), std::string::npos) << cut.error();
  std::remove(path.c_str());
}

TEST(PcapReader, ReadsPcapngWithItsInterfaceTimeResolution) {
  // Section header (little endian), an Ethernet interface with if_tsresol 9 (ns), one enhanced
  // packet block of a 15-byte frame at 3.000000005 s.
  const std::vector<std::uint8_t> file = {
      0x0a, 0x0d, 0x0d, 0x0a, 28,   0,    0,    0,    0x4d, 0x3c, 0x2b, 0x1a,
      1,    0,    0,    0,                                                  // SHB
      0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 28,   0,    0,    0,  //
      1,    0,    0,    0,    28,   0,    0,    0,    1,    0,    0,    0,
      0,    0,    0,    0,                                                  // IDB
      9,    0,    1,    0,    9,    0,    0,    0,    28,   0,    0,    0,  // if_tsresol
      6,    0,    0,    0,    48,   0,    0,    0,    0,    0,    0,    0,  // EPB, if 0
      0,    0,    0,    0,    0x05, 0x5e, 0xd0, 0xb2, 15,   0,    0,    0,
      15,   0,    0,    0,  // 3e9+5 ns
      0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 2,    0,    0,    0,    0,    7,
      0x89, 0x47, 0xab, 0,  // frame
      48,   0,    0,    0};
  const auto frames = parse_capture(file);
  ASSERT_TRUE(frames) << frames.error();
  ASSERT_EQ(frames->size(), 1u);
  EXPECT_EQ((*frames)[0].time,
            clock::WallTime{std::chrono::duration_cast<clock::WallClock::duration>(
                std::chrono::nanoseconds{3'000'000'005})});
  EXPECT_EQ((*frames)[0].source, (MacAddress{2, 0, 0, 0, 0, 7}));
  EXPECT_EQ((*frames)[0].payload, std::vector<std::uint8_t>{0xab});

  auto wrong_if = file;
  wrong_if[64] = 1;
  const auto e = parse_capture(wrong_if);
  ASSERT_FALSE(e);
  EXPECT_NE(e.error().find("interface 1"), std::string::npos) << e.error();
  EXPECT_FALSE(parse_capture(std::vector<std::uint8_t>{1, 2, 3, 4, 5}));
}

TEST(CapturingLink, RecordsSentAndReceivedFramesAndPassesThemOn) {
  const std::string path = ::testing::TempDir() + "/gn_capturing_test.pcap";
  auto pcap = PcapWriter::create(path);
  ASSERT_TRUE(pcap);
  clock::ManualClock clock{clock::WallTime{std::chrono::seconds{2}}};
  TestLink inner{{2, 0, 0, 0, 0, 1}};
  CapturingLink link{inner, *pcap, clock};
  int received = 0;
  link.set_receive_handler([&](const ReceivedFrame&) { ++received; });
  const std::uint8_t out[] = {0xaa};
  EXPECT_FALSE(link.send(kBroadcastMac, kEtherTypeGeoNetworking, out));
  inner.fail_sends_with(std::make_error_code(std::errc::network_down));
  EXPECT_TRUE(link.send(kBroadcastMac, kEtherTypeGeoNetworking, out));  // not recorded
  const std::uint8_t in[] = {0xbb, 0xcc};
  inner.inject({2, 0, 0, 0, 0, 7}, kBroadcastMac, kEtherTypeGeoNetworking, in,
               clock::WallTime{std::chrono::seconds{3}});
  EXPECT_EQ(received, 1);
  EXPECT_EQ(inner.sent().size(), 1u);
  ASSERT_TRUE(pcap->flush());
  const auto bytes = read_file(path);
  // File header, then a 15-byte frame and a 16-byte frame, each after a 16-byte record header.
  ASSERT_EQ(bytes.size(), 24u + 16 + 15 + 16 + 16);
  EXPECT_EQ(bytes[24], 2);                      // sent at 2 s
  EXPECT_EQ(bytes[24 + 16 + 15], 3);            // received at 3 s
  EXPECT_EQ(bytes[24 + 16 + 15 + 16 + 11], 7);  // received frame's source MAC
  EXPECT_EQ(bytes.back(), 0xcc);
  std::remove(path.c_str());
}

TEST(PcapWriter, UnwritablePathIsAnErrorNamingIt) {
  auto w = PcapWriter::create("/nonexistent-dir/x.pcap");
  ASSERT_FALSE(w);
  EXPECT_NE(w.error().find("'/nonexistent-dir/x.pcap'"), std::string::npos);
  EXPECT_NE(w.error().find("No such file"), std::string::npos);
}

}  // namespace
}  // namespace tb::its::link
