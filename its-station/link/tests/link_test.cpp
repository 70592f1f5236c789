#include <gtest/gtest.h>

#include <boost/asio/io_context.hpp>

#include "its-station/link/packet_socket_link.hpp"
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

}  // namespace
}  // namespace tb::its::link
