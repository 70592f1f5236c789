#include "network-emulator/radio/frame_tag.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <tuple>
#include <vector>

namespace tb::emu::radio {
namespace {

using Bytes = std::vector<std::uint8_t>;

/// An unsecured SHB carrying a CAM of @p station with generationDeltaTime @p gdt, laid out by
/// hand after EN 302 636-4-1 (9.6 Basic, 9.7 Common, 9.8.4 SHB), EN 302 636-5-1 (BTP-B) and
/// the CAM's UPER encoding (ItsPduHeader, then generationDeltaTime).
Bytes gn_cam(std::uint32_t station, std::uint16_t gdt, std::uint16_t port = 2001,
             std::uint8_t message_id = 2) {
  Bytes b = {0x11, 0x00, 0x50, 0x01,                           // Basic: version 1, NH Common
             0x20, 0x50, 0x02, 0x80, 0x00, 0x20, 0x01, 0x00};  // Common: NH BTP-B, TSB/SHB
  b.insert(b.end(), 24, 0x5A);                                 // SO position vector
  b.insert(b.end(), 4, 0x00);                                  // media-dependent data
  b.insert(b.end(), {static_cast<std::uint8_t>(port >> 8), static_cast<std::uint8_t>(port), 0, 0});
  b.insert(b.end(), {0x02, message_id, static_cast<std::uint8_t>(station >> 24),
                     static_cast<std::uint8_t>(station >> 16),
                     static_cast<std::uint8_t>(station >> 8), static_cast<std::uint8_t>(station),
                     static_cast<std::uint8_t>(gdt >> 8), static_cast<std::uint8_t>(gdt)});
  b.insert(b.end(), {0x40, 0x03, 0x80});  // the rest of the CAM: not read
  return b;
}

/// @p gn as TS 103 097 signs it: the basic header (NH secured packet), then the head of a
/// signedData whose payload is the rest of @p gn, with a @p long_length form of its length;
/// what follows the payload (header info, signer, signature) is not read.
Bytes secured(const Bytes& gn, bool long_length = false) {
  Bytes b(gn.begin(), gn.begin() + 4);
  b[0] = static_cast<std::uint8_t>((b[0] & 0xF0) | 2);
  const std::size_t n = gn.size() - 4;
  b.insert(b.end(), {0x03, 0x81, 0x00, 0x40, 0x03, 0x80});
  if (long_length)
    b.insert(b.end(), {0x82, static_cast<std::uint8_t>(n >> 8), static_cast<std::uint8_t>(n)});
  else
    b.push_back(static_cast<std::uint8_t>(n));
  b.insert(b.end(), gn.begin() + 4, gn.end());
  b.insert(b.end(), {0x40, 0x01, 0x24});  // headerInfo ...
  return b;
}

Bytes ethernet(const Bytes& gn, std::uint16_t ethertype = 0x8947) {
  Bytes f = {0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0x02, 0x00, 0x00, 0x00, 0x03, 0xE9};
  f.insert(f.end(),
           {static_cast<std::uint8_t>(ethertype >> 8), static_cast<std::uint8_t>(ethertype)});
  f.insert(f.end(), gn.begin(), gn.end());
  return f;
}

/// An OCB data frame as mac80211 sends it: @p fc0 0x88 QoS data (2 bytes QoS control), 0x08
/// plain data; addr1 broadcast, addr3 the wildcard BSSID; then LLC/SNAP.
Bytes ieee80211(const Bytes& gn, std::uint8_t fc0 = 0x88, std::uint8_t fc1 = 0x00) {
  Bytes f = {fc0, fc1, 0x00, 0x00};
  f.insert(f.end(), 6, 0xFF);                               // addr1
  f.insert(f.end(), {0x02, 0x00, 0x00, 0x00, 0x03, 0xE9});  // addr2
  f.insert(f.end(), 6, 0xFF);                               // addr3
  f.insert(f.end(), {0x10, 0x00});                          // sequence control
  if (fc0 & 0x80)
    f.insert(f.end(), {0x00, 0x00});  // QoS control
  f.insert(f.end(), {0xAA, 0xAA, 0x03, 0x00, 0x00, 0x00, 0x89, 0x47});
  f.insert(f.end(), gn.begin(), gn.end());
  return f;
}

TEST(PeekCam, ReadsStationAndGenerationTimeOfAnEthernetFrame) {
  EXPECT_EQ(peek_cam(ethernet(gn_cam(1001, 0xBEEF)), LinkFraming::kEthernet),
            (CamTag{1001, 0xBEEF}));
  EXPECT_EQ(peek_cam(ethernet(gn_cam(4294967295u, 0)), LinkFraming::kEthernet),
            (CamTag{4294967295u, 0}));
}

TEST(PeekCam, ReadsQosAndPlainDataFramesOf80211) {
  EXPECT_EQ(peek_cam(ieee80211(gn_cam(1002, 31245)), LinkFraming::kIeee80211),
            (CamTag{1002, 31245}));
  EXPECT_EQ(peek_cam(ieee80211(gn_cam(1002, 7), 0x08), LinkFraming::kIeee80211), (CamTag{1002, 7}));
}

TEST(PeekCam, ReadsTheSignedPayloadOfASecuredPacket) {
  EXPECT_EQ(peek_cam(ethernet(secured(gn_cam(1003, 4242))), LinkFraming::kEthernet),
            (CamTag{1003, 4242}));
  EXPECT_EQ(peek_cam(ieee80211(secured(gn_cam(1003, 4242), true)), LinkFraming::kIeee80211),
            (CamTag{1003, 4242}));
  // A head it does not know (another version, signer first, extDataHash, a length of three
  // octets): no CAM.
  for (std::size_t i : {4u, 5u, 7u, 8u, 9u}) {
    auto s = secured(gn_cam(1, 1));
    s[i] ^= i == 7 ? 0xC0 : 0x01;
    EXPECT_FALSE(peek_cam(ethernet(s), LinkFraming::kEthernet)) << i;
  }
  auto three = secured(gn_cam(1, 1), true);
  three[10] = 0x83;
  EXPECT_FALSE(peek_cam(ethernet(three), LinkFraming::kEthernet));
}

TEST(PeekCam, AnythingButAShbCamIsNoCam) {
  const auto eth = LinkFraming::kEthernet;
  EXPECT_FALSE(peek_cam(ethernet(gn_cam(1, 1, 2002)), eth));     // BTP port of DENMs
  EXPECT_FALSE(peek_cam(ethernet(gn_cam(1, 1, 2001, 1)), eth));  // a DENM's messageID
  EXPECT_FALSE(peek_cam(ethernet(gn_cam(1, 1), 0x0800), eth));   // IPv4
  auto other = gn_cam(1, 1);
  other[0] = 0x13;  // Basic header NH 3: neither common header nor secured packet
  EXPECT_FALSE(peek_cam(ethernet(other), eth));
  EXPECT_FALSE(peek_cam(ethernet(secured(gn_cam(1, 1, 2002))), eth));
  auto gbc = gn_cam(1, 1);
  gbc[5] = 0x41;  // Common header: GeoBroadcast circle
  EXPECT_FALSE(peek_cam(ethernet(gbc), eth));
  auto btp_a = gn_cam(1, 1);
  btp_a[4] = 0x10;  // Common header NH: BTP-A
  EXPECT_FALSE(peek_cam(ethernet(btp_a), eth));
  const auto cam = gn_cam(1, 1);
  EXPECT_FALSE(peek_cam(ieee80211(cam, 0x88, 0x40), LinkFraming::kIeee80211));  // protected
  EXPECT_FALSE(peek_cam(ieee80211(cam, 0x80), LinkFraming::kIeee80211));  // beacon (management)
  EXPECT_FALSE(peek_cam(ieee80211(cam, 0xC8), LinkFraming::kIeee80211));  // QoS null: no body
  // The framings are not mixed up.
  EXPECT_FALSE(peek_cam(ethernet(cam), LinkFraming::kIeee80211));
  EXPECT_FALSE(peek_cam(ieee80211(cam), eth));
}

TEST(PeekCam, EveryShorterFrameIsNoCam) {
  for (const auto& [frame, framing, rest] :
       {std::tuple{ethernet(gn_cam(1001, 9)), LinkFraming::kEthernet, 3},
        std::tuple{ieee80211(gn_cam(1001, 9)), LinkFraming::kIeee80211, 3},
        std::tuple{ethernet(secured(gn_cam(1001, 9))), LinkFraming::kEthernet, 6},
        std::tuple{ethernet(secured(gn_cam(1001, 9), true)), LinkFraming::kEthernet, 6}}) {
    // The identity ends 3 bytes before the CAM does (and 3 more of signedData follow).
    const std::size_t needed = frame.size() - static_cast<std::size_t>(rest);
    for (std::size_t n = 0; n < needed; ++n)
      EXPECT_FALSE(peek_cam(std::span(frame).first(n), framing)) << n;
    EXPECT_TRUE(peek_cam(std::span(frame).first(needed), framing));
  }
}

}  // namespace
}  // namespace tb::emu::radio
