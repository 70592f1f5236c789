#include "its-station/geonet/shared_packet_parser.hpp"

#include <algorithm>

namespace tb::its::geonet {

const Expected<Packet, ParseError>& SharedPacketParser::parse(std::span<const std::uint8_t> bytes) {
  if (last_ && std::ranges::equal(bytes, last_bytes_)) {
    ++reused_;
    // The held payload views the last caller's bytes, which may be gone: view this caller's.
    if (*last_)
      (*last_)->payload = bytes.subspan(payload_offset_, (*last_)->payload.size());
    return *last_;
  }
  ++parsed_;
  last_ = parse_packet(bytes);
  last_bytes_.assign(bytes.begin(), bytes.end());
  const Expected<Packet, ParseError>& p = *last_;
  payload_offset_ = p ? static_cast<std::size_t>(p->payload.data() - bytes.data()) : 0;
  sender_row_ =
      p ? senders_.row(source_position(p->extended).address.mid_key()) : SenderIndex::kNoRow;
  return p;
}

}  // namespace tb::its::geonet
