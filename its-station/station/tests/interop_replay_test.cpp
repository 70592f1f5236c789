// Frames another ETSI stack sent (Vanetza's socktap, shared/interop), replayed at their
// recorded times into a station joined as the program joins it: link → GN router → BTP → CA
// service → LDM. Every CAM the peer sent must reach the LDM, dated right.

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "common/clock/runtime.hpp"
#include "its-station/facilities/ca_service.hpp"
#include "its-station/link/pcap_reader.hpp"
#include "its-station/link/test_link.hpp"
#include "its-station/station/adapters.hpp"

namespace tb::its::station {
namespace {

using namespace std::chrono_literals;

std::string data_path(const std::string& name) {
  return std::string{TESTBED_INTEROP_DIR} + "/" + name;
}

/// Our station, a few metres from the peer's fixed position (48.1351 N, 11.583 E).
struct ReplayStation {
  explicit ReplayStation(clock::ManualRuntime& rt)
      : link({2, 0, 0, 0, 0, 0x42}),
        gn_position(position),
        router(rt, link, gn_position),
        btp(router),
        sender(btp),
        ldm(rt),
        ca(rt, position, nullptr, sender, ldm, config()) {
    btp.register_port(facilities::kBtpPortCam,
                      [this](const btp::Indication& ind, std::span<const std::uint8_t> p) {
                        ca.receive(p, ind.gn->rx_time);
                      });
    ldm.on_neighbour([this](const facilities::Neighbour&) { ++ldm_updates; });
  }
  static facilities::CaConfig config() {
    facilities::CaConfig c;
    c.station_id = 4242;
    return c;
  }
  void fix(clock::ManualRuntime& rt) {
    facilities::PositionFix f;
    f.time = rt.wall_now();
    f.received = rt.steady_now();
    f.latitude_deg = 48.13515;
    f.longitude_deg = 11.58305;
    f.heading_deg = 0;
    f.speed_mps = 0;
    f.position_confidence = facilities::PositionFix::Ellipse{3.0, 3.0, 0.0};
    position.inject(f);
  }

  link::TestLink link;
  facilities::InjectedPositionProvider position;
  GnPositionAdapter gn_position;
  geonet::Router router;
  btp::Dispatcher btp;
  BtpMessageSender sender;
  facilities::Ldm ldm;
  facilities::CaService ca;
  std::size_t ldm_updates = 0;
};

TEST(InteropReplay, EveryCamOfVanetzaSocktapReachesTheLdm) {
  const auto frames = link::read_capture(data_path("vanetza-socktap-cams-unsecured.pcap"));
  ASSERT_TRUE(frames) << frames.error();
  ASSERT_EQ(frames->size(), 110u);

  clock::ManualRuntime rt{frames->front().time - 1s};
  const clock::SteadyTime start = rt.steady_now();
  ReplayStation station(rt);
  station.fix(rt);
  for (const auto& f : *frames) {
    rt.advance_to(start + 1s + (f.time - frames->front().time));
    station.fix(rt);
    station.link.inject(f.source, f.destination, f.ethertype, f.payload, rt.wall_now());
  }

  EXPECT_EQ(station.router.stats().delivered, 110u);
  EXPECT_EQ(station.ca.counters().received, 110u);
  EXPECT_EQ(station.ca.counters().decode_errors, 0u);
  EXPECT_EQ(station.ldm_updates, 110u);
  const auto* peer = station.ldm.neighbour(2002);
  ASSERT_NE(peer, nullptr);
  EXPECT_NEAR(peer->latest().latitude_deg, 48.1351, 1e-7);
  EXPECT_NEAR(peer->latest().longitude_deg, 11.583, 1e-7);
  // The peer stamps generationDeltaTime in UTC: it names an instant just before reception,
  // not one a minute earlier.
  const auto age = peer->latest().received_wall - peer->latest().generation_time;
  EXPECT_GE(age, 0ms);
  EXPECT_LT(age, 100ms);
}

TEST(InteropReplay, TheSignedCaptureReadsAsSecuredGnPackets) {
  const auto frames = link::read_capture(data_path("vanetza-socktap-cams-dummy-signed.pcap"));
  ASSERT_TRUE(frames) << frames.error();
  ASSERT_GT(frames->size(), 100u);
  for (const auto& f : *frames) {
    EXPECT_EQ(f.ethertype, link::kEtherTypeGeoNetworking);
    ASSERT_GE(f.payload.size(), 1u);
    EXPECT_EQ(f.payload[0] & 0x0f, 2);  // basic header next header: secured packet
  }
}

}  // namespace
}  // namespace tb::its::station
