#include "its-station/facilities/shared_cam_decoder.hpp"

#include <algorithm>

namespace tb::its::facilities {

Expected<std::shared_ptr<const messages::Cam>, messages::CodecError> decode_shared_cam(
    std::span<const std::uint8_t> payload) {
  // Decoded in place, where the LDM keeps it: no copy of the 1.6 kB CAM.
  auto cam = std::make_shared<messages::Cam>();
  if (auto n = messages::decode(payload, *cam); !n)
    return Unexpected<messages::CodecError>{n.error()};
  return std::shared_ptr<const messages::Cam>(std::move(cam));
}

Expected<std::shared_ptr<const messages::Cam>, messages::CodecError> SharedCamDecoder::decode(
    std::span<const std::uint8_t> payload) {
  if (last_ && std::ranges::equal(payload, last_bytes_)) {
    ++reused_;
    return last_;
  }
  last_.reset();
  sender_row_ = SenderIndex::kNoRow;
  auto cam = decode_shared_cam(payload);
  if (!cam)
    return cam;
  ++decoded_;
  last_ = *cam;
  sender_row_ = senders_.row(last_->header.stationID);
  last_bytes_.assign(payload.begin(), payload.end());
  return cam;
}

}  // namespace tb::its::facilities
