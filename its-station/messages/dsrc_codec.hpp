#pragma once
/// @file UPER encoding and decoding of the DSRC (ISO TS 19091) pieces that SPATEM and MAPEM
/// share. Internal to its_messages; each function mirrors one ASN.1 type and names its
/// constraint; the widths follow from it (X.691 11.5.7.1).

#include <cstdint>
#include <optional>

#include "its-station/messages/cdd_codec.hpp"
#include "its-station/messages/dsrc.hpp"

namespace tb::its::messages::detail {

/// SEQUENCE (SIZE(Lb..Ub)) OF held in a BoundedVector of @p Cap < Ub elements: the length in
/// the bits of the module's range, refused above what is held (kSizeOutOfRange).
template <std::int64_t Lb, std::int64_t Ub>
inline std::size_t get_size(UperReader& r, std::size_t held, const char* f) {
  const std::size_t at = r.bit_position();
  const auto n = static_cast<std::size_t>(r.get_constrained<Lb, Ub>(f));
  if (r.ok() && n > held)
    r.fail_at(Error::kSizeOutOfRange, f, static_cast<std::int64_t>(n), at);
  return r.ok() ? n : 0;
}

/// A list SEQUENCE (SIZE(1..4)) OF RegionalExtension {{Reg-...}}: each element is
/// SEQUENCE {regionId RegionId (0..255), regExtValue open type}; skipped (X.691 11.2: the open
/// type is a length and that many octets), since no regional content is held.
inline void skip_regional_list(UperReader& r, const char* f) {
  const auto n = r.get_constrained<1, 4>(f);
  for (std::int64_t i = 0; i < n && r.ok(); ++i) {
    r.get_bits(8, f);  // regionId
    r.skip_open_type(f);
  }
}
/// One RegionalExtension (LaneAttributes.regional): regionId, then the open type, skipped.
inline void skip_regional(UperReader& r, const char* f) {
  r.get_bits(8, f);
  r.skip_open_type(f);
}

/// The extension bit and root index of a CHOICE with an extension marker (X.691 23.5-23.8): an
/// alternative added in a later version is kUnknownExtension (its value cannot be held).
inline unsigned get_choice_ext(UperReader& r, unsigned root_count, const char* f) {
  const std::size_t at = r.bit_position();
  if (r.get_bool(f)) {
    const auto idx = r.get_normally_small(f);
    if (r.ok())
      r.fail_at(Error::kUnknownExtension, f, static_cast<std::int64_t>(idx), at);
    return 0;
  }
  return static_cast<unsigned>(r.get_constrained(0, root_count - 1, f));
}

/// The optional list @p o, present and empty, reusing its storage when it was present already:
/// the SPAT and MapData lists are large enough (up to megabytes) that building a fresh one on
/// every decode would cost more than the decoding.
template <typename V>
inline V& reuse(std::optional<V>& o) {
  if (o) {
    o->clear();
    return *o;
  }
  return o.emplace();
}

// DescriptiveName ::= IA5String (SIZE(1..63))
inline void put(UperWriter& w, const DescriptiveName& n, const char* f) {
  put_ia5<1, 63>(w, n, f);
}
inline void get(UperReader& r, DescriptiveName& n, const char* f) {
  get_ia5<1, 63>(r, n, f);
}

// IntersectionReferenceID ::= SEQUENCE {region RoadRegulatorID (0..65535) OPTIONAL,
// id IntersectionID (0..65535)}, no extension marker
inline void put(UperWriter& w, const IntersectionReferenceID& id) {
  w.put_bool(id.region.has_value());
  if (id.region)
    w.put_bits(*id.region, 16);
  w.put_bits(id.id, 16);
}
inline void get(UperReader& r, IntersectionReferenceID& id) {
  id.region.reset();
  if (r.get_bool("IntersectionReferenceID"))
    id.region = static_cast<RoadRegulatorID>(r.get_bits(16, "region"));
  id.id = static_cast<IntersectionID>(r.get_bits(16, "id"));
}

// MsgCount ::= INTEGER (0..127)
inline void put_msg_count(UperWriter& w, MsgCount c, const char* f) {
  w.put_constrained<0, 127>(c, f);
}
inline MsgCount get_msg_count(UperReader& r, const char* f) {
  return static_cast<MsgCount>(r.get_bits(7, f));
}

// MinuteOfTheYear ::= INTEGER (0..527040)
inline void put_moy(UperWriter& w, MinuteOfTheYear m, const char* f) {
  w.put_constrained<0, 527040>(m, f);
}
inline MinuteOfTheYear get_moy(UperReader& r, const char* f) {
  return static_cast<MinuteOfTheYear>(r.get_constrained<0, 527040>(f));
}

}  // namespace tb::its::messages::detail
