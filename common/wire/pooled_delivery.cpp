#include "common/wire/pooled_delivery.hpp"

#include <algorithm>

namespace tb::wire {
namespace {

void put_u16(std::uint8_t* p, std::uint16_t v) {
  p[0] = static_cast<std::uint8_t>(v >> 8);
  p[1] = static_cast<std::uint8_t>(v);
}
void put_u32(std::uint8_t* p, std::uint32_t v) {
  p[0] = static_cast<std::uint8_t>(v >> 24);
  p[1] = static_cast<std::uint8_t>(v >> 16);
  p[2] = static_cast<std::uint8_t>(v >> 8);
  p[3] = static_cast<std::uint8_t>(v);
}

}  // namespace

std::string_view to_string(PooledDeliveryError e) {
  switch (e) {
    case PooledDeliveryError::kTooShort:
      return "shorter than the TBPD head";
    case PooledDeliveryError::kBadMagic:
      return "not TBPD (bad magic)";
    case PooledDeliveryError::kUnsupportedVersion:
      return "unsupported TBPD version";
    case PooledDeliveryError::kNoReceivers:
      return "no receivers (count 0)";
    case PooledDeliveryError::kTruncatedReceivers:
      return "receiver list longer than the bytes";
    case PooledDeliveryError::kInnerFrameTooShort:
      return "inner frame shorter than an Ethernet header";
    case PooledDeliveryError::kNotPooledDelivery:
      return "not a pooled-delivery frame (ethertype or size)";
  }
  return "unknown TBPD error";
}

std::vector<std::uint32_t> PooledDelivery::receivers() const {
  std::vector<std::uint32_t> ids(receiver_count());
  for (std::size_t i = 0; i < ids.size(); ++i)
    ids[i] = receiver(i);
  return ids;
}

std::size_t build_pooled_delivery(std::span<const std::uint32_t> receivers,
                                  std::span<const std::uint8_t> inner_frame,
                                  std::span<std::uint8_t> out) {
  if (receivers.empty() || receivers.size() > kMaxPooledReceivers ||
      inner_frame.size() < kEthernetHeaderSize)
    return 0;
  const std::size_t size = pooled_delivery_size(receivers.size(), inner_frame.size());
  if (out.size() < size)
    return 0;
  std::uint8_t* p = out.data();
  std::copy(kPooledDeliveryMagic.begin(), kPooledDeliveryMagic.end(), p);
  p[4] = kPooledDeliveryVersion;
  p[5] = 0;
  put_u16(p + 6, static_cast<std::uint16_t>(receivers.size()));
  p += kPooledDeliveryHeadSize;
  for (const std::uint32_t id : receivers) {
    put_u32(p, id);
    p += 4;
  }
  std::copy(inner_frame.begin(), inner_frame.end(), p);
  return size;
}

std::size_t build_pooled_delivery_frame(std::span<const std::uint32_t> receivers,
                                        std::span<const std::uint8_t> inner_frame,
                                        std::span<std::uint8_t> out) {
  if (out.size() < kEthernetHeaderSize)
    return 0;
  const std::size_t payload =
      build_pooled_delivery(receivers, inner_frame, out.subspan(kEthernetHeaderSize));
  if (payload == 0)
    return 0;
  std::fill_n(out.begin(), 6, std::uint8_t{0xFF});
  std::copy_n(inner_frame.begin() + 6, 6, out.begin() + 6);
  put_u16(out.data() + 12, kEthertypePooledDelivery);
  return kEthernetHeaderSize + payload;
}

std::vector<std::uint8_t> build_pooled_delivery_frame(std::span<const std::uint32_t> receivers,
                                                      std::span<const std::uint8_t> inner_frame) {
  std::vector<std::uint8_t> out(pooled_delivery_frame_size(receivers.size(), inner_frame.size()));
  out.resize(build_pooled_delivery_frame(receivers, inner_frame, out));
  return out;
}

Expected<PooledDelivery, PooledDeliveryError> parse_pooled_delivery(
    std::span<const std::uint8_t> payload) {
  if (payload.size() < kPooledDeliveryHeadSize)
    return Unexpected{PooledDeliveryError::kTooShort};
  if (!std::equal(kPooledDeliveryMagic.begin(), kPooledDeliveryMagic.end(), payload.begin()))
    return Unexpected{PooledDeliveryError::kBadMagic};
  if (payload[4] != kPooledDeliveryVersion)
    return Unexpected{PooledDeliveryError::kUnsupportedVersion};
  const std::size_t count = std::size_t{payload[6]} << 8 | payload[7];
  if (count == 0)
    return Unexpected{PooledDeliveryError::kNoReceivers};
  const auto rest = payload.subspan(kPooledDeliveryHeadSize);
  if (rest.size() < 4 * count)
    return Unexpected{PooledDeliveryError::kTruncatedReceivers};
  PooledDelivery d{rest.first(4 * count), rest.subspan(4 * count)};
  if (d.inner_frame.size() < kEthernetHeaderSize)
    return Unexpected{PooledDeliveryError::kInnerFrameTooShort};
  return d;
}

Expected<PooledDelivery, PooledDeliveryError> parse_pooled_delivery_frame(
    std::span<const std::uint8_t> frame) {
  if (frame.size() < kEthernetHeaderSize ||
      (std::uint16_t{frame[12]} << 8 | frame[13]) != kEthertypePooledDelivery)
    return Unexpected{PooledDeliveryError::kNotPooledDelivery};
  return parse_pooled_delivery(frame.subspan(kEthernetHeaderSize));
}

}  // namespace tb::wire
