#pragma once
// Helpers for router tests: positions around a fixed point and packets from other stations.

#include <vector>

#include "common/geodesy/local_frame.hpp"
#include "its-station/geonet/router.hpp"

namespace tb::its::geonet::testing {

using Bytes = std::vector<std::uint8_t>;

inline constexpr double kOriginLat = 48.15;
inline constexpr double kOriginLon = -1.6;

/// The point @p east / @p north metres from the origin.
inline GeoPoint at(double east, double north) {
  const geodesy::LocalFrame frame{{kOriginLat, kOriginLon, 0.0}};
  const auto g = frame.to_geodetic({east, north, 0.0});
  return {g.latitude_deg, g.longitude_deg};
}

inline link::MacAddress mac(std::uint8_t last) {
  return {0x02, 0x00, 0x00, 0x00, 0x00, last};
}

inline LongPositionVector remote_pv(std::uint8_t last, const GeoPoint& p, Timestamp tst) {
  LongPositionVector pv;
  pv.address = {false, StationType::kPassengerCar, mac(last)};
  pv.timestamp = tst;
  pv.latitude = to_tenth_micro_degree(p.latitude_deg);
  pv.longitude = to_tenth_micro_degree(p.longitude_deg);
  pv.position_accurate = true;
  return pv;
}

inline GeoArea circle_at(const GeoPoint& centre, std::uint16_t radius) {
  return {AreaShape::kCircle,
          to_tenth_micro_degree(centre.latitude_deg),
          to_tenth_micro_degree(centre.longitude_deg),
          radius,
          0,
          0};
}

struct PacketSpec {
  PacketType type = PacketType::kSingleHopBroadcast;
  LongPositionVector source;
  std::uint8_t rhl = 1;
  std::uint8_t mhl = 1;
  std::uint16_t sn = 0;
  GeoArea area{};
  clock::Duration lifetime = std::chrono::seconds{1};
  Bytes payload = {0x07, 0xd1, 0x00, 0x00, 0xca, 0xfe};
};

inline Bytes make_packet(const PacketSpec& s) {
  BasicHeader basic{kGnProtocolVersion, BasicNextHeader::kCommonHeader,
                    Lifetime::from_duration(s.lifetime), s.rhl};
  CommonHeader common{UpperProtocol::kBtpB, s.type, {}, true, 0, s.mhl};
  ExtendedHeader ext;
  switch (s.type) {
    case PacketType::kBeacon:
      ext = BeaconHeader{s.source};
      common.next_header = UpperProtocol::kAny;
      break;
    case PacketType::kSingleHopBroadcast:
      ext = ShbHeader{s.source, 0};
      break;
    case PacketType::kTopologicallyScopedBroadcast:
      ext = TsbHeader{s.sn, s.source};
      break;
    default:
      ext = GbcHeader{s.sn, s.source, s.area};
  }
  Bytes out(link::kMaxPayload);
  out.resize(
      serialize(basic, common, ext, s.type == PacketType::kBeacon ? Bytes{} : s.payload, out));
  return out;
}

}  // namespace tb::its::geonet::testing
