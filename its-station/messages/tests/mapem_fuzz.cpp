// libFuzzer target: the MAPEM decoder on arbitrary bytes. Whatever decodes must re-encode, and
// the re-encoding must decode to the same message and encode to the same bytes (the decoder
// accepts nothing the encoder would refuse).

#include <cstdint>
#include <cstdlib>
#include <memory>
#include <span>

#include "its-station/messages/mapem.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tb::its::messages;
  // Over a megabyte each: allocated once, reused (decode clears what a message lacks).
  static const auto first = std::make_unique<Mapem>();
  static const auto again = std::make_unique<Mapem>();
  if (!decode(std::span<const std::uint8_t>(data, size), *first))
    return 0;
  auto bytes = encode(*first);
  if (!bytes)
    std::abort();  // decoded but cannot be encoded: a range check missing on one side
  if (!decode(*bytes, *again) || !(*again == *first))
    std::abort();
  auto bytes2 = encode(*again);
  if (!bytes2 || *bytes2 != *bytes)
    std::abort();
  return 0;
}
