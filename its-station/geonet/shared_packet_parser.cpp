#include "its-station/geonet/shared_packet_parser.hpp"

#include <algorithm>

namespace tb::its::geonet {

Expected<Packet, ParseError> SharedPacketParser::parse(std::span<const std::uint8_t> bytes) {
  if (last_ && std::ranges::equal(bytes, last_bytes_)) {
    ++reused_;
    Expected<Packet, ParseError> out = *last_;
    // The held payload views the last caller's bytes, which may be gone: view this caller's.
    if (out)
      out->payload = bytes.subspan(payload_offset_, out->payload.size());
    return out;
  }
  ++parsed_;
  auto p = parse_packet(bytes);
  last_bytes_.assign(bytes.begin(), bytes.end());
  payload_offset_ = p ? static_cast<std::size_t>(p->payload.data() - bytes.data()) : 0;
  last_ = p;
  return p;
}

}  // namespace tb::its::geonet
