#pragma once
/// @file Writes Ethernet frames to a classic pcap file (libpcap format 2.4, LINKTYPE_ETHERNET),
/// so that what the stack sends or receives can be opened in Wireshark or tshark.

#include <cstdint>
#include <fstream>
#include <span>
#include <string>

#include "common/clock/clock.hpp"
#include "common/util/expected.hpp"
#include "its-station/link/link_layer.hpp"

namespace tb::its::link {

class PcapWriter {
 public:
  /// Creates (truncates) @p path and writes the file header; the error names the path.
  static Expected<PcapWriter, std::string> create(const std::string& path);

  /// Appends one frame: Ethernet II header from the arguments, then @p payload.
  bool write(clock::WallTime time, const MacAddress& destination, const MacAddress& source,
             std::uint16_t ethertype, std::span<const std::uint8_t> payload);
  bool flush();

 private:
  explicit PcapWriter(std::ofstream out) : out_(std::move(out)) {}
  std::ofstream out_;
};

}  // namespace tb::its::link
