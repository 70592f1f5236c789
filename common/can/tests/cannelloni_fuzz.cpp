// Fuzz target for cannelloni datagrams (CAN frames over UDP, several per datagram): any bytes
// through decode_cannelloni, which must not read out of bounds; whatever decodes must encode
// back to the same bytes, frame for frame.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>

#include "common/can/cannelloni.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> bytes(data, size);
  const auto packet = tb::can::decode_cannelloni(bytes);
  if (!packet)
    return 0;
  if (tb::can::cannelloni_size(packet->frames) != size)
    std::abort();
  const auto again = tb::can::encode_cannelloni(packet->sequence, packet->frames);
  if (again.size() != size || !std::equal(again.begin(), again.end(), bytes.begin()))
    std::abort();
  return 0;
}
