#pragma once
/// @file UPER encoding and decoding of the CDD (TS 102 894-2 V1.3.1) types that CAM and DENM
/// share. Internal to its_messages; every function mirrors one ASN.1 type, the widths follow
/// from its constraint (X.691 11.5.7.1), and the comment names that constraint.

#include <cstdint>
#include <optional>

#include "its-station/asn1/uper.hpp"
#include "its-station/messages/cdd.hpp"

namespace tb::its::messages::detail {

using asn1::Error;
using asn1::UperReader;
using asn1::UperWriter;

template <typename E>
inline void put_enum(UperWriter& w, E e, unsigned root_count, bool extensible, const char* f) {
  w.put_enumerated(static_cast<unsigned>(e), root_count, extensible, f);
}
template <typename E>
inline E get_enum(UperReader& r, unsigned root_count, bool extensible, const char* f) {
  return static_cast<E>(r.get_enumerated(root_count, extensible, f));
}

/// A fixed-size BIT STRING whose named bit n is (1 << n) in @p v; X.691 16.9: the bits in
/// order, bit 0 first, no length.
inline void put_named_bits(UperWriter& w, std::uint32_t v, unsigned size, const char* f) {
  if ((v >> size) != 0) {
    w.fail(Error::kValueOutOfRange, f, v);
    return;
  }
  std::uint32_t wire = 0;
  for (unsigned i = 0; i < size; ++i)
    wire |= ((v >> i) & 1u) << (size - 1 - i);
  w.put_bits(wire, size);
}
inline std::uint32_t get_named_bits(UperReader& r, unsigned size, const char* f) {
  const auto wire = static_cast<std::uint32_t>(r.get_bits(size, f));
  std::uint32_t v = 0;
  for (unsigned i = 0; i < size; ++i)
    v |= ((wire >> (size - 1 - i)) & 1u) << i;
  return v;
}

// ReferencePosition ::= SEQUENCE {latitude, longitude, positionConfidenceEllipse, altitude}
inline void put(UperWriter& w, const ReferencePosition& p) {
  w.put_constrained<-900000000, 900000001>(p.latitude, "latitude");
  w.put_constrained<-1800000000, 1800000001>(p.longitude, "longitude");
  const PosConfidenceEllipse& e = p.positionConfidenceEllipse;
  w.put_constrained<0, 4095>(e.semiMajorConfidence, "semiMajorConfidence");
  w.put_constrained<0, 4095>(e.semiMinorConfidence, "semiMinorConfidence");
  w.put_constrained<0, 3601>(e.semiMajorOrientation, "semiMajorOrientation");
  w.put_constrained<-100000, 800001>(p.altitude.altitudeValue, "altitudeValue");
  put_enum(w, p.altitude.altitudeConfidence, 16, false, "altitudeConfidence");
}
inline void get(UperReader& r, ReferencePosition& p) {
  p.latitude = static_cast<Latitude>(r.get_constrained<-900000000, 900000001>("latitude"));
  p.longitude = static_cast<Longitude>(r.get_constrained<-1800000000, 1800000001>("longitude"));
  PosConfidenceEllipse& e = p.positionConfidenceEllipse;
  e.semiMajorConfidence = static_cast<SemiAxisLength>(r.get_bits(12, "semiMajorConfidence"));
  e.semiMinorConfidence = static_cast<SemiAxisLength>(r.get_bits(12, "semiMinorConfidence"));
  e.semiMajorOrientation =
      static_cast<HeadingValue>(r.get_constrained<0, 3601>("semiMajorOrientation"));
  p.altitude.altitudeValue =
      static_cast<AltitudeValue>(r.get_constrained<-100000, 800001>("altitudeValue"));
  p.altitude.altitudeConfidence =
      static_cast<AltitudeConfidence>(r.get_bits(4, "altitudeConfidence"));
}

// DeltaReferencePosition ::= SEQUENCE {deltaLatitude, deltaLongitude, deltaAltitude}
inline void put(UperWriter& w, const DeltaReferencePosition& d) {
  w.put_constrained<-131071, 131072>(d.deltaLatitude, "deltaLatitude");
  w.put_constrained<-131071, 131072>(d.deltaLongitude, "deltaLongitude");
  w.put_constrained<-12700, 12800>(d.deltaAltitude, "deltaAltitude");
}
inline void get(UperReader& r, DeltaReferencePosition& d) {
  d.deltaLatitude = static_cast<DeltaLatitude>(r.get_constrained<-131071, 131072>("deltaLatitude"));
  d.deltaLongitude =
      static_cast<DeltaLongitude>(r.get_constrained<-131071, 131072>("deltaLongitude"));
  d.deltaAltitude = static_cast<DeltaAltitude>(r.get_constrained<-12700, 12800>("deltaAltitude"));
}

// PathDeltaTime ::= INTEGER (1..65535, ...)
inline void put_path_delta_time(UperWriter& w, PathDeltaTime t, const char* f) {
  if (t == 0) {  // below the root and not representable as an extension by this type
    w.fail(Error::kValueOutOfRange, f, 0);
    return;
  }
  w.put_bool(false);
  w.put_bits(t - 1u, 16);
}
inline PathDeltaTime get_path_delta_time(UperReader& r, const char* f) {
  return static_cast<PathDeltaTime>(r.get_constrained_ext<1, 65535>(f));
}

// PathPoint ::= SEQUENCE {pathPosition, pathDeltaTime OPTIONAL}
// PathHistory ::= SEQUENCE (SIZE(0..40)) OF PathPoint
inline void put(UperWriter& w, const PathHistory& h) {
  w.put_bits(h.size(), 6);  // size() <= 40 by the container
  for (const PathPoint& p : h) {
    w.put_bool(p.pathDeltaTime.has_value());
    put(w, p.pathPosition);
    if (p.pathDeltaTime)
      put_path_delta_time(w, *p.pathDeltaTime, "pathDeltaTime");
  }
}
inline void get(UperReader& r, PathHistory& h) {
  h.clear();
  const std::size_t at = r.bit_position();
  const auto n = static_cast<std::size_t>(r.get_bits(6, "pathHistory"));
  if (n > kPathHistoryMaxPoints) {
    r.fail_at(Error::kSizeOutOfRange, "pathHistory", static_cast<std::int64_t>(n), at);
    return;
  }
  for (std::size_t i = 0; i < n && r.ok(); ++i) {
    PathPoint& p = h.emplace_back();
    const bool has_time = r.get_bool("pathPoint");
    get(r, p.pathPosition);
    if (has_time)
      p.pathDeltaTime = get_path_delta_time(r, "pathDeltaTime");
  }
}

// Heading ::= SEQUENCE {headingValue (0..3601), headingConfidence (1..127)}
inline void put(UperWriter& w, const Heading& h) {
  w.put_constrained<0, 3601>(h.headingValue, "headingValue");
  w.put_constrained<1, 127>(h.headingConfidence, "headingConfidence");
}
inline void get(UperReader& r, Heading& h) {
  h.headingValue = static_cast<HeadingValue>(r.get_constrained<0, 3601>("headingValue"));
  h.headingConfidence =
      static_cast<HeadingConfidence>(r.get_constrained<1, 127>("headingConfidence"));
}

// Speed ::= SEQUENCE {speedValue (0..16383), speedConfidence (1..127)}
inline void put(UperWriter& w, const Speed& s) {
  w.put_constrained<0, 16383>(s.speedValue, "speedValue");
  w.put_constrained<1, 127>(s.speedConfidence, "speedConfidence");
}
inline void get(UperReader& r, Speed& s) {
  s.speedValue = static_cast<SpeedValue>(r.get_bits(14, "speedValue"));
  s.speedConfidence = static_cast<SpeedConfidence>(r.get_constrained<1, 127>("speedConfidence"));
}

// An acceleration: value (-160..161), AccelerationConfidence (0..102).
inline void put_acceleration(UperWriter& w, AccelerationValue v, AccelerationConfidence c,
                             const char* fv, const char* fc) {
  w.put_constrained<-160, 161>(v, fv);
  w.put_constrained<0, 102>(c, fc);
}
template <typename V, typename C>
inline void get_acceleration(UperReader& r, V& v, C& c, const char* fv, const char* fc) {
  v = static_cast<AccelerationValue>(r.get_constrained<-160, 161>(fv));
  c = static_cast<AccelerationConfidence>(r.get_constrained<0, 102>(fc));
}

// CauseCode ::= SEQUENCE {causeCode (0..255), subCauseCode (0..255), ...}; CDD version 1
// (protocolVersion 1) has no extension marker.
inline void put(UperWriter& w, const CauseCode& c, bool v1) {
  if (!v1)
    w.put_bool(false);
  w.put_bits(c.causeCode, 8);
  w.put_bits(c.subCauseCode, 8);
}
inline void get(UperReader& r, CauseCode& c, const char* f, bool v1) {
  const bool ext = !v1 && r.get_bool(f);
  c.causeCode = static_cast<CauseCodeType>(r.get_bits(8, "causeCode"));
  c.subCauseCode = static_cast<SubCauseCodeType>(r.get_bits(8, "subCauseCode"));
  if (ext)
    r.skip_sequence_extensions(f);
}

}  // namespace tb::its::messages::detail
