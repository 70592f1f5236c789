// libFuzzer target: any frame a station puts on the air must be tagged or rejected by peek_cam
// in either framing without reading outside it.

#include <cstdint>
#include <vector>

#include "network-emulator/radio/frame_tag.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // A copy of exactly this size, so that ASan sees a read one past the end.
  const std::vector<std::uint8_t> frame(data, data + size);
  using tb::emu::radio::LinkFraming;
  for (const auto framing : {LinkFraming::kEthernet, LinkFraming::kIeee80211}) {
    const auto tag = tb::emu::radio::peek_cam(frame, framing);
    if (tag) {
      volatile std::uint32_t sink = tag->station_id ^ tag->generation_delta_time;
      (void)sink;
    }
  }
  return 0;
}
