#pragma once
/// @file Reads Ethernet frames from a capture file, classic pcap (either byte order, µs or ns)
/// or pcapng (what dumpcap and Wireshark write), so that frames recorded from another stack can
/// be replayed into ours. Only LINKTYPE_ETHERNET interfaces are read; other blocks are skipped.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "common/clock/clock.hpp"
#include "common/util/expected.hpp"
#include "its-station/link/link_layer.hpp"

namespace tb::its::link {

struct CapturedFrame {
  clock::WallTime time{};
  MacAddress destination{};
  MacAddress source{};
  std::uint16_t ethertype = 0;
  std::vector<std::uint8_t> payload;  ///< after the Ethernet II header
};

/// Parses a whole capture held in memory. The error names what was wrong and at which offset;
/// no byte outside @p bytes is read, whatever they hold.
Expected<std::vector<CapturedFrame>, std::string> parse_capture(
    std::span<const std::uint8_t> bytes);

/// Reads and parses @p path; the error names the file.
Expected<std::vector<CapturedFrame>, std::string> read_capture(const std::string& path);

}  // namespace tb::its::link
