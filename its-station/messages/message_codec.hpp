#pragma once
/// @file The entry points that CAM and DENM share around their UPER codecs: encoding into a
/// vector, and decoding that insists on the whole buffer (a PDU followed by anything else is
/// an error, not a message). Internal to its_messages.

#include <cstdint>
#include <span>
#include <vector>

#include "common/util/expected.hpp"
#include "its-station/asn1/error.hpp"
#include "its-station/asn1/uper.hpp"

namespace tb::its::messages::detail {

/// Encodes @p msg with the message's own encode(msg, span) into a vector of at most
/// @p max_size bytes, trimmed to the encoding.
template <typename Msg>
Expected<std::vector<std::uint8_t>, asn1::CodecError> encode_to_vector(const Msg& msg,
                                                                       std::size_t max_size) {
  std::vector<std::uint8_t> out(max_size);
  auto n = encode(msg, std::span<std::uint8_t>(out));
  if (!n)
    return Unexpected<asn1::CodecError>{n.error()};
  out.resize(*n);
  return out;
}

/// Decodes one @p name PDU with @p get from all of @p bytes into @p out; returns the bytes
/// consumed, or the codec's error, or kTrailingData when bytes are left over.
template <typename Msg, typename Get>
Expected<std::size_t, asn1::CodecError> decode_whole(std::span<const std::uint8_t> bytes, Msg& out,
                                                     const char* name, Get get) {
  asn1::UperReader r(bytes);
  get(r, out);
  if (!r.ok())
    return Unexpected<asn1::CodecError>{r.error()};
  if (r.octets_consumed() != bytes.size())
    return Unexpected<asn1::CodecError>{asn1::CodecError{
        asn1::Error::kTrailingData, name,
        static_cast<std::int64_t>(bytes.size() - r.octets_consumed()), r.octets_consumed() * 8}};
  return r.octets_consumed();
}

/// The message's own decode(bytes, msg), returning the message.
template <typename Msg>
Expected<Msg, asn1::CodecError> decode_value(std::span<const std::uint8_t> bytes) {
  Msg msg;
  auto n = decode(bytes, msg);
  if (!n)
    return Unexpected<asn1::CodecError>{n.error()};
  return msg;
}

}  // namespace tb::its::messages::detail
