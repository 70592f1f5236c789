#pragma once
/// @file The Signal Phase And Timing Extended Message of ETSI TS 103 301 v2.1.1 (module
/// SPATEM-PDU-Descriptions version 2): ItsPduHeader + the SPAT of ISO TS 19091 (2018), and its
/// UPER (ITU-T X.691 unaligned) codec.
///
/// Every root component of SPAT, IntersectionState, MovementState, MovementEvent,
/// TimeChangeDetails, AdvisorySpeed and ConnectionManeuverAssist is held, except the regional
/// extensions (skipped when decoding, none encoded: dsrc.hpp). Lists are bounded as in dsrc.hpp.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "common/util/expected.hpp"
#include "its-station/asn1/error.hpp"
#include "its-station/messages/dsrc.hpp"

namespace tb::its::messages {

using asn1::CodecError;

/// SPAT ::= SEQUENCE {timeStamp?, name?, intersections, regional?, ...}.
struct SPAT {
  std::optional<MinuteOfTheYear> timeStamp;
  std::optional<DescriptiveName> name;
  IntersectionStateList intersections;  ///< SIZE(1..): at least one
  friend bool operator==(const SPAT&, const SPAT&) = default;
};

/// SPATEM ::= SEQUENCE {header ItsPduHeader, spat SPAT}; protocolVersion 2, messageID
/// spatem (4).
struct Spatem {
  ItsPduHeader header{kProtocolVersion, kMessageIdSpatem, 0};
  SPAT spat;
  friend bool operator==(const Spatem&, const Spatem&) = default;
};

/// Largest UPER encoding of a Spatem as bounded here, in bytes, with room to spare (4
/// intersections of 64 signal groups with 16 events each at their largest take about 180 kB): an
/// encoding that does not fit a caller's smaller buffer is kBufferTooSmall.
inline constexpr std::size_t kSpatemMaxEncodedSize = 256 * 1024;

/// Encodes @p spatem into @p out and returns the bytes written, or an error naming the field
/// outside its constraint (kValueOutOfRange / kSizeOutOfRange); messageID must be spatem (4)
/// and protocolVersion 2. Nothing allocates.
Expected<std::size_t, CodecError> encode(const Spatem& spatem, std::span<std::uint8_t> out);
/// As above into a vector trimmed to the encoding (allocates kSpatemMaxEncodedSize first).
Expected<std::vector<std::uint8_t>, CodecError> encode(const Spatem& spatem);

/// Decodes one UPER-encoded SPATEM (protocolVersion 2) that fills @p bytes; returns the bytes
/// consumed. Never reads outside @p bytes. After an error @p out is unspecified.
Expected<std::size_t, CodecError> decode(std::span<const std::uint8_t> bytes, Spatem& out);
/// sizeof(Spatem) is about 0.5 MB: prefer decode(bytes, out) into a long-lived object.
Expected<Spatem, CodecError> decode_spatem(std::span<const std::uint8_t> bytes);

}  // namespace tb::its::messages
