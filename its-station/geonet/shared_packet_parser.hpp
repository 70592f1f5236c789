#pragma once
/// @file The GN headers of one frame parsed once for the stations of a thread that hear it one
/// after the other (station-host's pooled stations, issue 33): at 300 in range the per-station
/// parse of the same bytes was a sixth of the host's CPU. The parser also looks the frame's
/// source up once in a SenderIndex, where each station's location table finds its entry.

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "common/util/sender_index.hpp"
#include "its-station/geonet/packet.hpp"

namespace tb::its::geonet {

class SharedPacketParser {
 public:
  /// What parse_packet(@p bytes) gives, its payload a view into @p bytes: from the last call
  /// when the bytes are the same, else parsed now. parse_packet is a function of the bytes
  /// alone, so a station cannot tell the two apart. Valid until the next call (a station
  /// handles its frame before the next one is handed out); not copied per station, as the
  /// copy stalled on its own stores.
  const Expected<Packet, ParseError>& parse(std::span<const std::uint8_t> bytes);

  /// The row of the last parsed packet's source (its GnAddress::mid_key()) in senders(), or
  /// SenderIndex::kNoRow when it did not parse.
  std::uint32_t sender_row() const { return sender_row_; }
  /// Where the location tables of the stations sharing this parser cache their entries.
  SenderIndex& senders() { return senders_; }

  std::uint64_t parsed() const { return parsed_; }
  std::uint64_t reused() const { return reused_; }

 private:
  std::vector<std::uint8_t> last_bytes_;
  std::optional<Expected<Packet, ParseError>> last_;
  std::size_t payload_offset_ = 0;  ///< of the last packet's payload in its bytes
  SenderIndex senders_;
  std::uint32_t sender_row_ = SenderIndex::kNoRow;
  std::uint64_t parsed_ = 0;
  std::uint64_t reused_ = 0;
};

}  // namespace tb::its::geonet
