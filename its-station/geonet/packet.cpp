#include "its-station/geonet/packet.hpp"

#include <array>
#include <chrono>

#include "common/util/bytes.hpp"

namespace tb::its::geonet {

using namespace std::chrono_literals;

std::uint64_t GnAddress::mid_key() const {
  std::uint64_t key = 0;
  for (const auto b : mid)
    key = (key << 8) | b;
  return key;
}

namespace {

constexpr std::array<clock::Duration, 4> kLifetimeBase = {50ms, 1s, 10s, 100s};

void write_address(ByteWriter& w, const GnAddress& a) {
  // M (bit 15) | ST (bits 14..10) | reserved (bits 9..0), then the 48-bit MID.
  const auto head =
      static_cast<std::uint16_t>((a.manually_configured ? 0x8000u : 0u) |
                                 ((static_cast<unsigned>(a.station_type) & 0x1fu) << 10));
  w.be<std::uint16_t>(head);
  w.write(a.mid);
}

GnAddress read_address(ByteReader& r) {
  GnAddress a;
  const auto head = r.be<std::uint16_t>();
  a.manually_configured = (head & 0x8000u) != 0;
  a.station_type = static_cast<StationType>((head >> 10) & 0x1fu);
  r.read(a.mid);
  return a;
}

}  // namespace

void write_long_position_vector(ByteWriter& w, const LongPositionVector& pv) {
  write_address(w, pv.address);
  w.be<std::uint32_t>(pv.timestamp);
  w.be<std::int32_t>(pv.latitude);
  w.be<std::int32_t>(pv.longitude);
  // PAI (bit 15) | S (15-bit two's complement).
  const auto speed_bits = static_cast<std::uint16_t>(pv.speed) & 0x7fffu;
  w.be<std::uint16_t>(
      static_cast<std::uint16_t>((pv.position_accurate ? 0x8000u : 0u) | speed_bits));
  w.be<std::uint16_t>(pv.heading);
}

LongPositionVector read_long_position_vector(ByteReader& r) {
  LongPositionVector pv;
  pv.address = read_address(r);
  pv.timestamp = r.be<std::uint32_t>();
  pv.latitude = r.be<std::int32_t>();
  pv.longitude = r.be<std::int32_t>();
  const auto pai_speed = r.be<std::uint16_t>();
  pv.position_accurate = (pai_speed & 0x8000u) != 0;
  // Sign-extend the 15-bit speed.
  auto speed = static_cast<std::int32_t>(pai_speed & 0x7fffu);
  if (speed & 0x4000)
    speed -= 0x8000;
  pv.speed = static_cast<std::int16_t>(speed);
  pv.heading = r.be<std::uint16_t>();
  return pv;
}

void write_short_position_vector(ByteWriter& w, const ShortPositionVector& pv) {
  write_address(w, pv.address);
  w.be<std::uint32_t>(pv.timestamp);
  w.be<std::int32_t>(pv.latitude);
  w.be<std::int32_t>(pv.longitude);
}

ShortPositionVector read_short_position_vector(ByteReader& r) {
  ShortPositionVector pv;
  pv.address = read_address(r);
  pv.timestamp = r.be<std::uint32_t>();
  pv.latitude = r.be<std::int32_t>();
  pv.longitude = r.be<std::int32_t>();
  return pv;
}

namespace {

struct TypeCode {
  std::uint8_t ht;
  std::uint8_t hst;
};

TypeCode type_code(PacketType t) {
  switch (t) {
    case PacketType::kBeacon:
      return {1, 0};
    case PacketType::kGeoBroadcastCircle:
      return {4, 0};
    case PacketType::kGeoBroadcastRectangle:
      return {4, 1};
    case PacketType::kGeoBroadcastEllipse:
      return {4, 2};
    case PacketType::kSingleHopBroadcast:
      return {5, 0};
    case PacketType::kTopologicallyScopedBroadcast:
      return {5, 1};
  }
  return {0, 0};
}

}  // namespace

Lifetime Lifetime::from_duration(clock::Duration d) {
  if (d <= clock::Duration::zero())
    return Lifetime{0};
  for (std::size_t base = 0; base < kLifetimeBase.size(); ++base) {
    const auto unit = kLifetimeBase[base];
    const auto multiplier = (d + unit - clock::Duration{1}) / unit;  // round up
    if (multiplier <= 63)
      return Lifetime{static_cast<std::uint8_t>((multiplier << 2) | base)};
  }
  return Lifetime{static_cast<std::uint8_t>((63u << 2) | 3u)};
}

clock::Duration Lifetime::duration() const {
  return (encoded >> 2) * kLifetimeBase[encoded & 3u];
}

std::uint8_t TrafficClass::encode() const {
  return static_cast<std::uint8_t>((store_carry_forward ? 0x80u : 0u) |
                                   (channel_offload ? 0x40u : 0u) | (id & 0x3fu));
}

TrafficClass TrafficClass::decode(std::uint8_t raw) {
  return TrafficClass{(raw & 0x80u) != 0, (raw & 0x40u) != 0,
                      static_cast<std::uint8_t>(raw & 0x3fu)};
}

std::string to_string(PacketType t) {
  switch (t) {
    case PacketType::kBeacon:
      return "Beacon";
    case PacketType::kGeoBroadcastCircle:
      return "GBC circle";
    case PacketType::kGeoBroadcastRectangle:
      return "GBC rectangle";
    case PacketType::kGeoBroadcastEllipse:
      return "GBC ellipse";
    case PacketType::kSingleHopBroadcast:
      return "SHB";
    case PacketType::kTopologicallyScopedBroadcast:
      return "TSB";
  }
  return "unknown";
}

std::string to_string(ParseError e) {
  switch (e) {
    case ParseError::kTruncatedBasicHeader:
      return "truncated basic header";
    case ParseError::kUnsupportedVersion:
      return "basic header version is not 1";
    case ParseError::kSecuredPacket:
      return "secured packet (security not supported)";
    case ParseError::kUnknownBasicNextHeader:
      return "unknown basic header next header";
    case ParseError::kTruncatedCommonHeader:
      return "truncated common header";
    case ParseError::kUnknownHeaderType:
      return "unknown header type/subtype";
    case ParseError::kUnsupportedHeaderType:
      return "unsupported header type (GeoUnicast, GeoAnycast, location service)";
    case ParseError::kTruncatedExtendedHeader:
      return "truncated extended header";
    case ParseError::kPayloadLengthExceedsFrame:
      return "payload length exceeds the frame";
  }
  return "unknown parse error";
}

const LongPositionVector& source_position(const ExtendedHeader& h) {
  return std::visit([](const auto& x) -> const LongPositionVector& { return x.source_position; },
                    h);
}

std::size_t header_size(PacketType type) {
  std::size_t ext = 0;
  switch (type) {
    case PacketType::kBeacon:
      ext = kBeaconHeaderSize;
      break;
    case PacketType::kSingleHopBroadcast:
      ext = kShbHeaderSize;
      break;
    case PacketType::kTopologicallyScopedBroadcast:
      ext = kTsbHeaderSize;
      break;
    default:
      ext = kGbcHeaderSize;
  }
  return kBasicHeaderSize + kCommonHeaderSize + ext;
}

Expected<Packet, ParseError> parse_packet(std::span<const std::uint8_t> bytes) {
  ByteReader r{bytes};
  Packet p;
  // Basic header (clause 9.6): Version (4) | NH (4), reserved, LT, RHL.
  const auto version_nh = r.be<std::uint8_t>();
  r.skip(1);
  p.basic.lifetime.encoded = r.be<std::uint8_t>();
  p.basic.remaining_hop_limit = r.be<std::uint8_t>();
  if (!r.ok())
    return Unexpected{ParseError::kTruncatedBasicHeader};
  p.basic.version = version_nh >> 4;
  if (p.basic.version != kGnProtocolVersion)
    return Unexpected{ParseError::kUnsupportedVersion};
  const auto bnh = version_nh & 0x0fu;
  if (bnh == static_cast<unsigned>(BasicNextHeader::kSecuredPacket))
    return Unexpected{ParseError::kSecuredPacket};
  if (bnh != static_cast<unsigned>(BasicNextHeader::kCommonHeader))
    return Unexpected{ParseError::kUnknownBasicNextHeader};
  p.basic.next_header = BasicNextHeader::kCommonHeader;

  // Common header (clause 9.7): NH (4) | reserved (4), HT (4) | HST (4), TC, flags, PL, MHL,
  // reserved.
  const auto nh = r.be<std::uint8_t>() >> 4;
  const auto ht_hst = r.be<std::uint8_t>();
  const auto tc = r.be<std::uint8_t>();
  const auto flags = r.be<std::uint8_t>();
  p.common.payload_length = r.be<std::uint16_t>();
  p.common.maximum_hop_limit = r.be<std::uint8_t>();
  r.skip(1);
  if (!r.ok())
    return Unexpected{ParseError::kTruncatedCommonHeader};
  // NH values above IPv6 are reserved; pass them up as they are and let the upper layer refuse.
  p.common.next_header = static_cast<UpperProtocol>(nh);
  p.common.traffic_class = TrafficClass::decode(tc);
  p.common.mobile = (flags & 0x80u) != 0;

  const unsigned ht = ht_hst >> 4;
  const unsigned hst = ht_hst & 0x0fu;
  switch (ht) {
    case 1:
      if (hst != 0)
        return Unexpected{ParseError::kUnknownHeaderType};
      p.common.type = PacketType::kBeacon;
      p.extended = BeaconHeader{read_long_position_vector(r)};
      break;
    case 4: {
      if (hst > 2)
        return Unexpected{ParseError::kUnknownHeaderType};
      p.common.type =
          static_cast<PacketType>(static_cast<unsigned>(PacketType::kGeoBroadcastCircle) + hst);
      GbcHeader g;
      g.sequence_number = r.be<std::uint16_t>();
      r.skip(2);
      g.source_position = read_long_position_vector(r);
      g.area.shape = static_cast<AreaShape>(hst);
      g.area.latitude = r.be<std::int32_t>();
      g.area.longitude = r.be<std::int32_t>();
      g.area.distance_a = r.be<std::uint16_t>();
      g.area.distance_b = r.be<std::uint16_t>();
      g.area.angle = r.be<std::uint16_t>();
      r.skip(2);
      p.extended = g;
      break;
    }
    case 5:
      if (hst == 0) {
        p.common.type = PacketType::kSingleHopBroadcast;
        ShbHeader s;
        s.source_position = read_long_position_vector(r);
        s.media_dependent = r.be<std::uint32_t>();
        p.extended = s;
      } else if (hst == 1) {
        p.common.type = PacketType::kTopologicallyScopedBroadcast;
        TsbHeader t;
        t.sequence_number = r.be<std::uint16_t>();
        r.skip(2);
        t.source_position = read_long_position_vector(r);
        p.extended = t;
      } else {
        return Unexpected{ParseError::kUnknownHeaderType};
      }
      break;
    case 2:
      if (hst != 0)
        return Unexpected{ParseError::kUnknownHeaderType};
      return Unexpected{ParseError::kUnsupportedHeaderType};
    case 3:
      if (hst > 2)
        return Unexpected{ParseError::kUnknownHeaderType};
      return Unexpected{ParseError::kUnsupportedHeaderType};
    case 6:
      if (hst > 1)
        return Unexpected{ParseError::kUnknownHeaderType};
      return Unexpected{ParseError::kUnsupportedHeaderType};
    default:
      return Unexpected{ParseError::kUnknownHeaderType};
  }
  if (!r.ok())
    return Unexpected{ParseError::kTruncatedExtendedHeader};
  if (p.common.payload_length > r.remaining())
    return Unexpected{ParseError::kPayloadLengthExceedsFrame};
  p.payload = r.rest().first(p.common.payload_length);
  return p;
}

std::size_t serialize(const BasicHeader& basic, const CommonHeader& common,
                      const ExtendedHeader& extended, std::span<const std::uint8_t> payload,
                      std::span<std::uint8_t> out) {
  if (payload.size() > 0xffff)
    return 0;
  ByteWriter w{out};
  w.be<std::uint8_t>(static_cast<std::uint8_t>((basic.version << 4) |
                                               (static_cast<unsigned>(basic.next_header) & 0x0fu)));
  w.be<std::uint8_t>(0);
  w.be<std::uint8_t>(basic.lifetime.encoded);
  w.be<std::uint8_t>(basic.remaining_hop_limit);

  const TypeCode code = type_code(common.type);
  w.be<std::uint8_t>(static_cast<std::uint8_t>(static_cast<unsigned>(common.next_header) << 4));
  w.be<std::uint8_t>(static_cast<std::uint8_t>((code.ht << 4) | code.hst));
  w.be<std::uint8_t>(common.traffic_class.encode());
  w.be<std::uint8_t>(common.mobile ? 0x80 : 0x00);
  w.be<std::uint16_t>(static_cast<std::uint16_t>(payload.size()));
  w.be<std::uint8_t>(common.maximum_hop_limit);
  w.be<std::uint8_t>(0);

  std::visit(
      [&](const auto& h) {
        using H = std::decay_t<decltype(h)>;
        if constexpr (std::is_same_v<H, BeaconHeader>) {
          write_long_position_vector(w, h.source_position);
        } else if constexpr (std::is_same_v<H, ShbHeader>) {
          write_long_position_vector(w, h.source_position);
          w.be<std::uint32_t>(h.media_dependent);
        } else if constexpr (std::is_same_v<H, TsbHeader>) {
          w.be<std::uint16_t>(h.sequence_number);
          w.be<std::uint16_t>(0);
          write_long_position_vector(w, h.source_position);
        } else {
          w.be<std::uint16_t>(h.sequence_number);
          w.be<std::uint16_t>(0);
          write_long_position_vector(w, h.source_position);
          w.be<std::int32_t>(h.area.latitude);
          w.be<std::int32_t>(h.area.longitude);
          w.be<std::uint16_t>(h.area.distance_a);
          w.be<std::uint16_t>(h.area.distance_b);
          w.be<std::uint16_t>(h.area.angle);
          w.be<std::uint16_t>(0);
        }
      },
      extended);
  w.write(payload);
  return w.ok() ? w.position() : 0;
}

}  // namespace tb::its::geonet
