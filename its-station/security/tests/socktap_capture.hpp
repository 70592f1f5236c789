#pragma once
/// @file The secured packets of Vanetza socktap's capture (`shared/interop`, README there), for
/// tests that decode and verify what another stack signed.

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "its-station/link/pcap_reader.hpp"

namespace tb::its::security::test {

/// What follows the GN basic header of each frame: an Ieee1609Dot2Data. Throws, naming the
/// file and frame, when a frame is no secured GeoNetworking packet.
inline std::vector<std::vector<std::uint8_t>> socktap_secured_packets() {
  const std::string path =
      std::string(TESTBED_INTEROP_DIR) + "/vanetza-socktap-cams-dummy-signed.pcap";
  auto frames = link::read_capture(path);
  if (!frames)
    throw std::runtime_error(frames.error());
  std::vector<std::vector<std::uint8_t>> packets;
  for (const auto& f : *frames) {
    // Basic header (4 octets), next header 2 = secured packet (EN 302 636-4-1 9.6).
    if (f.ethertype != 0x8947 || f.payload.size() <= 4 || (f.payload[0] & 0x0f) != 2)
      throw std::runtime_error(path + ": frame " + std::to_string(packets.size() + 1) +
                               " is no secured GeoNetworking packet");
    packets.emplace_back(f.payload.begin() + 4, f.payload.end());
  }
  return packets;
}

}  // namespace tb::its::security::test
