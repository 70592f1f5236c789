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

// ClosedLanes: CDD version 2 SEQUENCE {innerhardShoulderStatus, outerhardShoulderStatus,
// drivingLaneStatus BIT STRING (SIZE(1..13)) (all OPTIONAL), ...}; version 1 SEQUENCE
// {hardShoulderStatus OPTIONAL, drivingLaneStatus BIT STRING (SIZE(1..14)), ...} (cdd.hpp).
inline void put(UperWriter& w, const ClosedLanes& l, bool v1) {
  w.put_bool(false);
  if (v1) {
    if (l.innerhardShoulderStatus) {
      w.fail(Error::kValueOutOfRange, "innerhardShoulderStatus", 1);  // no such field in v1
      return;
    }
    if (!l.drivingLaneStatus) {
      w.fail(Error::kValueOutOfRange, "drivingLaneStatus", 0);  // mandatory in v1
      return;
    }
    w.put_bool(l.outerhardShoulderStatus.has_value());
    if (l.outerhardShoulderStatus)
      put_enum(w, *l.outerhardShoulderStatus, 3, false, "hardShoulderStatus");
    w.put_constrained<1, 14>(l.drivingLaneStatus->size, "drivingLaneStatus");
  } else {
    w.put_bool(l.innerhardShoulderStatus.has_value());
    w.put_bool(l.outerhardShoulderStatus.has_value());
    w.put_bool(l.drivingLaneStatus.has_value());
    if (l.innerhardShoulderStatus)
      put_enum(w, *l.innerhardShoulderStatus, 3, false, "innerhardShoulderStatus");
    if (l.outerhardShoulderStatus)
      put_enum(w, *l.outerhardShoulderStatus, 3, false, "outerhardShoulderStatus");
    if (!l.drivingLaneStatus)
      return;
    // BIT STRING (SIZE(1..13)): size - 1 in 4 bits, then the bits (X.691 16.11).
    w.put_constrained<1, 13>(l.drivingLaneStatus->size, "drivingLaneStatus");
  }
  if (w.ok())
    put_named_bits(w, l.drivingLaneStatus->bits, l.drivingLaneStatus->size, "drivingLaneStatus");
}
inline void get(UperReader& r, ClosedLanes& l, bool v1) {
  l = ClosedLanes{};
  const bool ext = r.get_bool("closedLanes");
  if (v1) {
    if (r.get_bool("closedLanes"))
      l.outerhardShoulderStatus = get_enum<HardShoulderStatus>(r, 3, false, "hardShoulderStatus");
    DrivingLaneStatus& d = l.drivingLaneStatus.emplace();
    d.size = static_cast<std::uint8_t>(r.get_constrained<1, 14>("drivingLaneStatus"));
    if (r.ok())
      d.bits = static_cast<std::uint16_t>(get_named_bits(r, d.size, "drivingLaneStatus"));
  } else {
    const auto present = r.get_bits(3, "closedLanes");
    if (present & 4)
      l.innerhardShoulderStatus =
          get_enum<HardShoulderStatus>(r, 3, false, "innerhardShoulderStatus");
    if (present & 2)
      l.outerhardShoulderStatus =
          get_enum<HardShoulderStatus>(r, 3, false, "outerhardShoulderStatus");
    if (present & 1) {
      DrivingLaneStatus& d = l.drivingLaneStatus.emplace();
      d.size = static_cast<std::uint8_t>(r.get_constrained<1, 13>("drivingLaneStatus"));
      if (r.ok())
        d.bits = static_cast<std::uint16_t>(get_named_bits(r, d.size, "drivingLaneStatus"));
    }
  }
  if (ext)
    r.skip_sequence_extensions("closedLanes");
}

// ---- Character strings (X.691 30)
// ----------------------------------------------------------------

/// Length of a SEQUENCE OF / string with SIZE(Lb..Ub): size - Lb in the range's bits
/// (X.691 11.9.4.1), none for a fixed size.
template <std::int64_t Lb, std::int64_t Ub>
inline void put_size(UperWriter& w, std::size_t n, const char* f) {
  if (n < static_cast<std::size_t>(Lb) || n > static_cast<std::size_t>(Ub)) {
    w.fail(Error::kSizeOutOfRange, f, static_cast<std::int64_t>(n));
    return;
  }
  w.put_constrained<Lb, Ub>(static_cast<std::int64_t>(n), f);
}
/// SIZE(Lb..Ub, ...): the extension bit, then the root size; sizes outside the root are
/// kUnknownExtension on decoding, as for every extension value these types cannot hold.
template <std::int64_t Lb, std::int64_t Ub>
inline void put_size_ext(UperWriter& w, std::size_t n, const char* f) {
  w.put_bool(false);
  put_size<Lb, Ub>(w, n, f);
}
template <std::int64_t Lb, std::int64_t Ub>
inline std::size_t get_size_ext(UperReader& r, const char* f) {
  const std::size_t at = r.bit_position();
  if (r.get_bool(f)) {
    const std::size_t n = r.get_length(f);
    if (r.ok())
      r.fail_at(Error::kUnknownExtension, f, static_cast<std::int64_t>(n), at);
    return 0;
  }
  return static_cast<std::size_t>(r.get_constrained<Lb, Ub>(f));
}

/// IA5String (SIZE(Lb..Ub)): the length, then 7 bits per character, its code (X.691 30.5.4:
/// 128 characters, each value fits its 7 bits).
template <std::int64_t Lb, std::int64_t Ub, std::size_t N>
inline void put_ia5(UperWriter& w, const CharString<N>& s, const char* f) {
  static_assert(static_cast<std::size_t>(Ub) <= N);
  if constexpr (Lb != Ub)
    put_size<Lb, Ub>(w, s.size(), f);
  else if (s.size() != static_cast<std::size_t>(Lb))
    w.fail(Error::kSizeOutOfRange, f, static_cast<std::int64_t>(s.size()));
  for (char c : s) {
    const auto code = static_cast<unsigned char>(c);
    if (code > 127) {
      w.fail(Error::kValueOutOfRange, f, code);
      return;
    }
    w.put_bits(code, 7);
  }
}
template <std::int64_t Lb, std::int64_t Ub, std::size_t N>
inline void get_ia5(UperReader& r, CharString<N>& s, const char* f) {
  static_assert(static_cast<std::size_t>(Ub) <= N);
  s.clear();
  std::size_t n = static_cast<std::size_t>(Lb);
  if constexpr (Lb != Ub)
    n = static_cast<std::size_t>(r.get_constrained<Lb, Ub>(f));
  for (std::size_t i = 0; i < n && r.ok(); ++i)
    s.push_back(static_cast<char>(r.get_bits(7, f)));
}

/// NumericString (SIZE(Lb..Ub)): the length, then 4 bits per character, its index in the
/// alphabet " 0123456789" (X.691 30.5.4: 11 characters, '9' does not fit 4 bits as itself).
template <std::int64_t Lb, std::int64_t Ub, std::size_t N>
inline void put_numeric(UperWriter& w, const CharString<N>& s, const char* f) {
  put_size<Lb, Ub>(w, s.size(), f);
  for (char c : s) {
    if (c != ' ' && (c < '0' || c > '9')) {
      w.fail(Error::kValueOutOfRange, f, static_cast<unsigned char>(c));
      return;
    }
    w.put_bits(c == ' ' ? 0u : static_cast<unsigned>(c - '0') + 1u, 4);
  }
}
template <std::int64_t Lb, std::int64_t Ub, std::size_t N>
inline void get_numeric(UperReader& r, CharString<N>& s, const char* f) {
  static_assert(static_cast<std::size_t>(Ub) <= N);
  s.clear();
  const std::size_t at = r.bit_position();
  const auto n = static_cast<std::size_t>(r.get_constrained<Lb, Ub>(f));
  for (std::size_t i = 0; i < n && r.ok(); ++i) {
    const auto v = static_cast<unsigned>(r.get_bits(4, f));
    if (v > 10) {
      if (r.ok())
        r.fail_at(Error::kValueOutOfRange, f, v, at);
      return;
    }
    s.push_back(v == 0 ? ' ' : static_cast<char>('0' + v - 1));
  }
}

/// Characters of a well-formed UTF-8 octet string, or -1 when it is not well formed.
inline int utf8_characters(const std::uint8_t* p, std::size_t n) {
  int chars = 0;
  for (std::size_t i = 0; i < n; ++chars) {
    const std::uint8_t b = p[i];
    const std::size_t len = b < 0x80           ? 1
                            : (b >> 5) == 0x6  ? 2
                            : (b >> 4) == 0xE  ? 3
                            : (b >> 3) == 0x1E ? 4
                                               : 0;
    if (len == 0 || i + len > n)
      return -1;
    for (std::size_t k = 1; k < len; ++k)
      if ((p[i + k] & 0xC0) != 0x80)
        return -1;
    i += len;
  }
  return chars;
}

/// UTF8String (SIZE(1..24)): not a known-multiplier type, so the size constraint is not PER-
/// visible (X.691 30.6): an unconstrained length in octets, then the octets. The constraint is
/// still checked here, in characters, on both sides.
inline void put_utf8(UperWriter& w, const BoundedVector<std::uint8_t, 96>& s, const char* f) {
  const int chars = utf8_characters(s.begin(), s.size());
  if (chars < 1 || chars > 24) {
    w.fail(chars < 0 ? Error::kValueOutOfRange : Error::kSizeOutOfRange, f, chars);
    return;
  }
  w.put_length(s.size(), f);
  for (std::uint8_t b : s)
    w.put_bits(b, 8);
}
inline void get_utf8(UperReader& r, BoundedVector<std::uint8_t, 96>& s, const char* f) {
  s.clear();
  const std::size_t at = r.bit_position();
  const std::size_t n = r.get_length(f);
  if (!r.ok())
    return;
  if (n > s.capacity()) {
    r.fail_at(Error::kSizeOutOfRange, f, static_cast<std::int64_t>(n), at);
    return;
  }
  for (std::size_t i = 0; i < n && r.ok(); ++i)
    s.push_back(static_cast<std::uint8_t>(r.get_bits(8, f)));
  if (!r.ok())
    return;
  const int chars = utf8_characters(s.begin(), s.size());
  if (chars < 1 || chars > 24)
    r.fail_at(chars < 0 ? Error::kValueOutOfRange : Error::kSizeOutOfRange, f, chars, at);
}

// DangerousGoodsExtended (cdd.hpp): CDD version 2 has the extension marker and a NumericString
// phoneNumber, version 1 neither.
inline void put(UperWriter& w, const DangerousGoodsExtended& g, bool v1) {
  if (!v1)
    w.put_bool(false);
  w.put_bool(g.emergencyActionCode.has_value());
  w.put_bool(g.phoneNumber.has_value());
  w.put_bool(g.companyName.has_value());
  w.put_enumerated(g.dangerousGoodsType, 20, false, "dangerousGoodsType");
  w.put_constrained<0, 9999>(g.unNumber, "unNumber");
  w.put_bool(g.elevatedTemperature);
  w.put_bool(g.tunnelsRestricted);
  w.put_bool(g.limitedQuantity);
  if (g.emergencyActionCode)
    put_ia5<1, 24>(w, *g.emergencyActionCode, "emergencyActionCode");
  if (g.phoneNumber) {
    if (v1)
      put_ia5<1, 24>(w, *g.phoneNumber, "phoneNumber");
    else
      put_numeric<1, 16>(w, *g.phoneNumber, "phoneNumber");
  }
  if (g.companyName)
    put_utf8(w, *g.companyName, "companyName");
}
inline void get(UperReader& r, DangerousGoodsExtended& g, bool v1) {
  g = DangerousGoodsExtended{};
  const bool ext = !v1 && r.get_bool("carryingDangerousGoods");
  const auto present = r.get_bits(3, "carryingDangerousGoods");
  g.dangerousGoodsType =
      static_cast<DangerousGoodsBasic>(r.get_enumerated(20, false, "dangerousGoodsType"));
  g.unNumber = static_cast<std::uint16_t>(r.get_constrained<0, 9999>("unNumber"));
  g.elevatedTemperature = r.get_bool("elevatedTemperature");
  g.tunnelsRestricted = r.get_bool("tunnelsRestricted");
  g.limitedQuantity = r.get_bool("limitedQuantity");
  if (present & 4)
    get_ia5<1, 24>(r, g.emergencyActionCode.emplace(), "emergencyActionCode");
  if (present & 2) {
    if (v1)
      get_ia5<1, 24>(r, g.phoneNumber.emplace(), "phoneNumber");
    else
      get_numeric<1, 16>(r, g.phoneNumber.emplace(), "phoneNumber");
  }
  if (present & 1)
    get_utf8(r, g.companyName.emplace(), "companyName");
  if (ext)
    r.skip_sequence_extensions("carryingDangerousGoods");
}

}  // namespace tb::its::messages::detail
