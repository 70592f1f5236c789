#pragma once
/// @file The Map Extended Message of ETSI TS 103 301 v2.1.1 (module MAPEM-PDU-Descriptions
/// version 2): ItsPduHeader + the MapData of ISO TS 19091 (2018), and its UPER (ITU-T X.691
/// unaligned) codec.
///
/// Held: MapData's root components but roadSegments, which is refused (kUnsupported, field
/// "roadSegments"); intersections with every GenericLane component (node lists of node-XY1..6
/// and node-LatLon offsets with their attributes, computed lanes, connections with their signal
/// groups, overlays); dataParameters; restrictionList. Refused too (kUnsupported, named): a
/// node's LaneDataAttributeList (`data`), the regional alternatives of NodeOffsetPointXY and
/// RestrictionUserType. Skipped: regional extensions and preemptPriorityData (dsrc.hpp).

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

/// MapData ::= SEQUENCE {timeStamp?, msgIssueRevision, layerType?, layerID?, intersections?,
/// roadSegments?, dataParameters?, restrictionList?, regional?, ...}.
struct MapData {
  std::optional<MinuteOfTheYear> timeStamp;
  MsgCount msgIssueRevision = 0;
  std::optional<LayerType> layerType;
  std::optional<LayerID> layerID;
  std::optional<IntersectionGeometryList> intersections;
  std::optional<DataParameters> dataParameters;
  std::optional<RestrictionClassList> restrictionList;
  friend bool operator==(const MapData&, const MapData&) = default;
};

/// MAPEM ::= SEQUENCE {header ItsPduHeader, map MapData}; protocolVersion 2, messageID
/// mapem (5).
struct Mapem {
  ItsPduHeader header{kProtocolVersion, kMessageIdMapem, 0};
  MapData map;
  friend bool operator==(const Mapem&, const Mapem&) = default;
};

/// Largest UPER encoding of a Mapem as bounded here, in bytes, with room to spare (4
/// intersections of 64 lanes of 63 nodes, every optional at its largest, take about 590 kB).
inline constexpr std::size_t kMapemMaxEncodedSize = 640 * 1024;

/// As for Spatem (spatem.hpp): encode into @p out, return the bytes written or the error naming
/// the field; messageID must be mapem (5), protocolVersion 2.
Expected<std::size_t, CodecError> encode(const Mapem& mapem, std::span<std::uint8_t> out);
Expected<std::vector<std::uint8_t>, CodecError> encode(const Mapem& mapem);

/// Decodes one UPER-encoded MAPEM (protocolVersion 2) that fills @p bytes; returns the bytes
/// consumed. Never reads outside @p bytes. After an error @p out is unspecified.
Expected<std::size_t, CodecError> decode(std::span<const std::uint8_t> bytes, Mapem& out);
/// sizeof(Mapem) is about 1.8 MB: prefer decode(bytes, out) into a long-lived object.
Expected<Mapem, CodecError> decode_mapem(std::span<const std::uint8_t> bytes);

}  // namespace tb::its::messages
