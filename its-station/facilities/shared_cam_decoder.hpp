#pragma once
/// @file Decoded CAMs shared between the CA services of one thread: the pooled stations of a
/// station-host hear the same frame one after the other, and each decoding it anew would keep
/// 300 copies of every neighbour's CAM (300 × 300 × 1.6 kB) and decode it 300 times (issue 33).
/// It also looks the sender up once in a SenderIndex, where each station's LDM finds it.

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "common/util/expected.hpp"
#include "common/util/sender_index.hpp"
#include "its-station/messages/cam.hpp"

namespace tb::its::facilities {

/// Decodes CAMs and hands out the same immutable object for the same bytes heard in a row.
/// Not thread-safe: one per thread that runs CA services.
class SharedCamDecoder {
 public:
  /// The CAM of @p payload: the last one decoded when the bytes are the same, else decoded now.
  Expected<std::shared_ptr<const messages::Cam>, messages::CodecError> decode(
      std::span<const std::uint8_t> payload);

  /// The row of the last decoded CAM's sender (its StationID) in senders(), or
  /// SenderIndex::kNoRow after an undecodable payload.
  std::uint32_t sender_row() const { return sender_row_; }
  /// Where the LDMs of the CA services sharing this decoder cache their neighbours.
  SenderIndex& senders() { return senders_; }

  std::uint64_t decoded() const { return decoded_; }
  std::uint64_t reused() const { return reused_; }

 private:
  std::vector<std::uint8_t> last_bytes_;
  std::shared_ptr<const messages::Cam> last_;  ///< null after an undecodable payload
  SenderIndex senders_;
  std::uint32_t sender_row_ = SenderIndex::kNoRow;
  std::uint64_t decoded_ = 0;
  std::uint64_t reused_ = 0;
};

/// One CAM decoded into an object of its own (a station without a SharedCamDecoder).
Expected<std::shared_ptr<const messages::Cam>, messages::CodecError> decode_shared_cam(
    std::span<const std::uint8_t> payload);

}  // namespace tb::its::facilities
