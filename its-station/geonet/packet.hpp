#pragma once
/// @file GeoNetworking packet headers of EN 302 636-4-1 V1.4.1 (clause 9), unsecured, and their
/// encoding. parse_packet() is a pure function of the received bytes.

#include <cstdint>
#include <span>
#include <string>
#include <variant>

#include "common/util/bytes.hpp"
#include "common/util/expected.hpp"
#include "its-station/geonet/timestamp.hpp"
#include "its-station/link/link_layer.hpp"

namespace tb::its::geonet {

/// ITS-S type of the GN address (clause 9.3; the StationType values of CDD TS 102 894-2).
enum class StationType : std::uint8_t {
  kUnknown = 0,
  kPedestrian = 1,
  kCyclist = 2,
  kMoped = 3,
  kMotorcycle = 4,
  kPassengerCar = 5,
  kBus = 6,
  kLightTruck = 7,
  kHeavyTruck = 8,
  kTrailer = 9,
  kSpecialVehicle = 10,
  kTram = 11,
  kRoadSideUnit = 15,
};

/// GN_ADDR (clause 6.3): M (1 bit) | ST (5 bits) | reserved (10 bits) | MID (48 bits).
struct GnAddress {
  /// M = 1 for a manually configured address, 0 for the initial one.
  bool manually_configured = false;
  StationType station_type = StationType::kUnknown;
  /// The MID is the station's link-layer (MAC) address.
  link::MacAddress mid{};

  std::uint64_t mid_key() const;
  bool operator==(const GnAddress&) const = default;
};

/// Long position vector (clause 9.5.2), in its wire units.
struct LongPositionVector {
  GnAddress address;
  Timestamp timestamp = 0;
  std::int32_t latitude = 0;       ///< 1/10 micro-degree
  std::int32_t longitude = 0;      ///< 1/10 micro-degree
  bool position_accurate = false;  ///< PAI
  std::int16_t speed = 0;          ///< 0.01 m/s, 15-bit signed
  std::uint16_t heading = 0;       ///< 0.1 degree from north, clockwise
  bool operator==(const LongPositionVector&) const = default;
};
inline constexpr std::size_t kLongPositionVectorSize = 24;

/// Short position vector (clause 9.5.3): the destination of GeoUnicast and LS replies, which
/// this router does not handle yet; the codec below covers it for when it does.
struct ShortPositionVector {
  GnAddress address;
  Timestamp timestamp = 0;
  std::int32_t latitude = 0;
  std::int32_t longitude = 0;
  bool operator==(const ShortPositionVector&) const = default;
};
inline constexpr std::size_t kShortPositionVectorSize = 20;

/// Position vector codecs; a read past the end leaves @p r failed (check r.ok()).
void write_long_position_vector(ByteWriter& w, const LongPositionVector& pv);
LongPositionVector read_long_position_vector(ByteReader& r);
void write_short_position_vector(ByteWriter& w, const ShortPositionVector& pv);
ShortPositionVector read_short_position_vector(ByteReader& r);

/// Basic header NH (clause 9.6.2).
enum class BasicNextHeader : std::uint8_t { kAny = 0, kCommonHeader = 1, kSecuredPacket = 2 };
/// Common header NH (clause 9.7.2): the upper protocol.
enum class UpperProtocol : std::uint8_t { kAny = 0, kBtpA = 1, kBtpB = 2, kIpv6 = 3 };

/// Packet lifetime LT (clause 9.6.4): multiplier (6 bits) × base (2 bits: 50 ms, 1 s, 10 s, 100 s).
struct Lifetime {
  std::uint8_t encoded = 0;
  static Lifetime from_duration(clock::Duration d);  ///< rounds up to the next encodable value
  clock::Duration duration() const;
};

inline constexpr std::uint8_t kGnProtocolVersion = 1;

struct BasicHeader {
  std::uint8_t version = kGnProtocolVersion;
  BasicNextHeader next_header = BasicNextHeader::kCommonHeader;
  Lifetime lifetime;
  std::uint8_t remaining_hop_limit = 1;
};
inline constexpr std::size_t kBasicHeaderSize = 4;

/// HT and HST (clause 9.7.4), flattened.
enum class PacketType : std::uint8_t {
  kBeacon,
  kGeoBroadcastCircle,
  kGeoBroadcastRectangle,
  kGeoBroadcastEllipse,
  kSingleHopBroadcast,
  kTopologicallyScopedBroadcast,
};
std::string to_string(PacketType t);

/// Traffic class (clause 9.7.5): SCF | channel offload | TC ID (6 bits).
struct TrafficClass {
  bool store_carry_forward = false;
  bool channel_offload = false;
  std::uint8_t id = 0;
  std::uint8_t encode() const;
  static TrafficClass decode(std::uint8_t raw);
  bool operator==(const TrafficClass&) const = default;
};

struct CommonHeader {
  UpperProtocol next_header = UpperProtocol::kBtpB;
  PacketType type = PacketType::kSingleHopBroadcast;
  TrafficClass traffic_class;
  bool mobile = true;  ///< Flags bit 0 (itsGnIsMobile)
  std::uint16_t payload_length = 0;
  std::uint8_t maximum_hop_limit = 1;
};
inline constexpr std::size_t kCommonHeaderSize = 8;

/// Shape of a geographical area (EN 302 931; the GBC header subtype).
enum class AreaShape : std::uint8_t { kCircle = 0, kRectangle = 1, kEllipse = 2 };

/// The destination area fields of the GBC header (clause 9.8.5), in wire units.
struct GeoArea {
  AreaShape shape = AreaShape::kCircle;
  std::int32_t latitude = 0;     ///< centre, 1/10 micro-degree
  std::int32_t longitude = 0;    ///< centre, 1/10 micro-degree
  std::uint16_t distance_a = 0;  ///< metres: radius, or half length along the azimuth
  std::uint16_t distance_b = 0;  ///< metres: half width (0 for a circle)
  std::uint16_t angle = 0;       ///< degrees, azimuth of the a axis from north, clockwise
  bool operator==(const GeoArea&) const = default;
};

struct BeaconHeader {
  LongPositionVector source_position;
};
inline constexpr std::size_t kBeaconHeaderSize = 24;

/// SHB extended header (clause 9.8.4): source PV and 4 bytes of media-dependent data (DCC).
struct ShbHeader {
  LongPositionVector source_position;
  std::uint32_t media_dependent = 0;
};
inline constexpr std::size_t kShbHeaderSize = 28;

struct TsbHeader {
  std::uint16_t sequence_number = 0;
  LongPositionVector source_position;
};
inline constexpr std::size_t kTsbHeaderSize = 28;

struct GbcHeader {
  std::uint16_t sequence_number = 0;
  LongPositionVector source_position;
  GeoArea area;
};
inline constexpr std::size_t kGbcHeaderSize = 44;

using ExtendedHeader = std::variant<BeaconHeader, ShbHeader, TsbHeader, GbcHeader>;

const LongPositionVector& source_position(const ExtendedHeader& h);

/// A decoded packet; payload points into the parsed bytes.
struct Packet {
  BasicHeader basic;
  CommonHeader common;
  ExtendedHeader extended;
  std::span<const std::uint8_t> payload;
};

enum class ParseError {
  kTruncatedBasicHeader,
  kUnsupportedVersion,  ///< clause 10.3.3: a receiver drops other versions
  kSecuredPacket,       ///< NH = secured packet: no security layer yet
  kUnknownBasicNextHeader,
  kTruncatedCommonHeader,
  kUnknownHeaderType,      ///< HT/HST not defined by the standard
  kUnsupportedHeaderType,  ///< GeoUnicast, GeoAnycast, LS: defined but not implemented
  kTruncatedExtendedHeader,
  kPayloadLengthExceedsFrame,
};
std::string to_string(ParseError e);

/// Parses a GN packet (the frame's payload after the Ethernet header). Never reads past
/// @p bytes; bytes after the payload length are link padding and are ignored.
Expected<Packet, ParseError> parse_packet(std::span<const std::uint8_t> bytes);

/// Size of the headers for @p type, from the basic header to the end of the extended header.
std::size_t header_size(PacketType type);

/// Encodes the headers and @p payload into @p out; returns the bytes written, or 0 if @p out
/// is too small. The common header's payload length is taken from @p payload.
std::size_t serialize(const BasicHeader& basic, const CommonHeader& common,
                      const ExtendedHeader& extended, std::span<const std::uint8_t> payload,
                      std::span<std::uint8_t> out);

}  // namespace tb::its::geonet
