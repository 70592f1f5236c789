// libFuzzer target: any bytes as a capture file. The reader must not read outside them, and a
// frame it returns always carries at least an Ethernet header's worth of data.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>

#include "its-station/link/pcap_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto frames = tb::its::link::parse_capture(std::span(data, size));
  if (frames) {
    std::size_t total = 0;
    for (const auto& f : *frames)
      total += f.payload.size() + 14;
    if (total > size)
      std::abort();  // more frame bytes than the file held
  }
  return 0;
}
