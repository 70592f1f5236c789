#include "network-emulator/radio/federation_datagram.hpp"

#include <bit>
#include <cmath>

namespace tb::emu::radio {
namespace {

template <typename T>
void put(std::vector<std::uint8_t>& out, T v) {
  for (int shift = 8 * (static_cast<int>(sizeof(T)) - 1); shift >= 0; shift -= 8)
    out.push_back(static_cast<std::uint8_t>(static_cast<std::uint64_t>(v) >> shift));
}

std::uint64_t get_be(const std::uint8_t* p, std::size_t n) {
  std::uint64_t v = 0;
  for (std::size_t i = 0; i < n; ++i)
    v = v << 8 | p[i];
  return v;
}

bool put_head(std::string_view node, FederationKind kind, std::vector<std::uint8_t>& out) {
  out.clear();
  if (node.empty() || node.size() > kMaxFederationNodeName)
    return false;
  out.insert(out.end(), kFederationMagic.begin(), kFederationMagic.end());
  out.push_back(kFederationVersion);
  out.push_back(static_cast<std::uint8_t>(kind));
  out.push_back(static_cast<std::uint8_t>(node.size()));
  out.insert(out.end(), node.begin(), node.end());
  return true;
}

}  // namespace

std::string_view to_string(FederationError e) {
  switch (e) {
    case FederationError::kTooShort:
      return "shorter than the federation head";
    case FederationError::kBadMagic:
      return "not a federation datagram (bad magic)";
    case FederationError::kUnsupportedVersion:
      return "unsupported federation version";
    case FederationError::kUnknownKind:
      return "unknown datagram kind";
    case FederationError::kBadNodeName:
      return "bad node name length";
    case FederationError::kTruncated:
      return "fields cut short";
    case FederationError::kBadFrameLength:
      return "frame length disagrees with the datagram";
    case FederationError::kTrailingBytes:
      return "bytes after the heartbeat";
    case FederationError::kBadPosition:
      return "position not a finite number";
  }
  return "unknown federation error";
}

bool encode_federated_frame(std::string_view node, StationId sender,
                            const std::array<double, 3>* position, std::int64_t tx_unix_ns,
                            std::span<const std::uint8_t> frame, std::vector<std::uint8_t>& out) {
  if (frame.size() > kMaxFederatedFrame || !put_head(node, FederationKind::kFrame, out)) {
    out.clear();
    return false;
  }
  put(out, std::uint32_t{sender});
  put(out, static_cast<std::uint8_t>(position ? 1 : 0));
  put(out, std::uint8_t{0});
  put(out, static_cast<std::uint16_t>(frame.size()));
  put(out, static_cast<std::uint64_t>(tx_unix_ns));
  for (int k = 0; k < 3; ++k)
    put(out, std::bit_cast<std::uint64_t>(position ? (*position)[k] : 0.0));
  out.insert(out.end(), frame.begin(), frame.end());
  return true;
}

bool encode_federation_heartbeat(std::string_view node, std::int64_t tx_unix_ns,
                                 std::vector<std::uint8_t>& out) {
  if (!put_head(node, FederationKind::kHeartbeat, out))
    return false;
  put(out, static_cast<std::uint64_t>(tx_unix_ns));
  return true;
}

Expected<FederationDatagram, FederationError> decode_federation_datagram(
    std::span<const std::uint8_t> bytes) {
  using U = Unexpected<FederationError>;
  if (bytes.size() < kFederationHeadSize)
    return U{FederationError::kTooShort};
  if (!std::equal(kFederationMagic.begin(), kFederationMagic.end(), bytes.begin()))
    return U{FederationError::kBadMagic};
  if (bytes[4] != kFederationVersion)
    return U{FederationError::kUnsupportedVersion};
  FederationDatagram d;
  if (bytes[5] == static_cast<std::uint8_t>(FederationKind::kFrame))
    d.kind = FederationKind::kFrame;
  else if (bytes[5] == static_cast<std::uint8_t>(FederationKind::kHeartbeat))
    d.kind = FederationKind::kHeartbeat;
  else
    return U{FederationError::kUnknownKind};
  const std::size_t name_size = bytes[6];
  if (name_size == 0 || name_size > kMaxFederationNodeName ||
      name_size > bytes.size() - kFederationHeadSize)
    return U{FederationError::kBadNodeName};
  d.node = std::string_view(reinterpret_cast<const char*>(bytes.data() + kFederationHeadSize),
                            name_size);
  const std::span<const std::uint8_t> rest = bytes.subspan(kFederationHeadSize + name_size);
  if (d.kind == FederationKind::kHeartbeat) {
    if (rest.size() < kFederationHeartbeatFieldsSize)
      return U{FederationError::kTruncated};
    if (rest.size() > kFederationHeartbeatFieldsSize)
      return U{FederationError::kTrailingBytes};
    d.tx_unix_ns = static_cast<std::int64_t>(get_be(rest.data(), 8));
    return d;
  }
  if (rest.size() < kFederationFrameFieldsSize)
    return U{FederationError::kTruncated};
  const std::uint8_t* p = rest.data();
  d.sender = static_cast<StationId>(get_be(p, 4));
  d.has_position = (p[4] & 1) != 0;  // the other flag bits and the reserved byte: ignored
  const std::size_t frame_size = get_be(p + 6, 2);
  d.tx_unix_ns = static_cast<std::int64_t>(get_be(p + 8, 8));
  for (int k = 0; k < 3; ++k) {
    d.position[k] = std::bit_cast<double>(get_be(p + 16 + 8 * k, 8));
    if (d.has_position && !std::isfinite(d.position[k]))
      return U{FederationError::kBadPosition};
  }
  if (!d.has_position)
    d.position = {};
  if (frame_size > kMaxFederatedFrame || frame_size != rest.size() - kFederationFrameFieldsSize)
    return U{FederationError::kBadFrameLength};
  d.frame = rest.subspan(kFederationFrameFieldsSize);
  return d;
}

}  // namespace tb::emu::radio
