// libFuzzer target: the DENM decoder on arbitrary bytes. Whatever decodes must re-encode, and
// the re-encoding must decode to the same message and encode to the same bytes (the decoder
// accepts nothing the encoder would refuse).

#include <cstdint>
#include <cstdlib>
#include <span>

#include "its-station/messages/denm.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tb::its::messages;
  auto msg = decode_denm(std::span<const std::uint8_t>(data, size));
  if (!msg)
    return 0;
  auto bytes = encode(*msg);
  if (!bytes)
    std::abort();  // decoded but cannot be encoded: a range check missing on one side
  auto again = decode_denm(*bytes);
  if (!again || !(*again == *msg))
    std::abort();
  auto bytes2 = encode(*again);
  if (!bytes2 || *bytes2 != *bytes)
    std::abort();
  return 0;
}
