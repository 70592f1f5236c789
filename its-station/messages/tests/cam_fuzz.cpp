// libFuzzer target: the CAM decoder on arbitrary bytes. Whatever decodes must re-encode, and
// the re-encoding must decode to the same message and encode to the same bytes (the decoder
// accepts nothing the encoder would refuse).

#include <cstdint>
#include <cstdlib>
#include <span>

#include "its-station/messages/cam.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tb::its::messages;
  auto cam = decode_cam(std::span<const std::uint8_t>(data, size));
  if (!cam)
    return 0;
  auto bytes = encode(*cam);
  if (!bytes)
    std::abort();  // decoded but cannot be encoded: a range check missing on one side
  auto again = decode_cam(*bytes);
  if (!again || !(*again == *cam))
    std::abort();
  auto bytes2 = encode(*again);
  if (!bytes2 || *bytes2 != *bytes)
    std::abort();
  return 0;
}
