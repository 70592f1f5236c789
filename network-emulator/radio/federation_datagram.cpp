#include "network-emulator/radio/federation_datagram.hpp"

#include <bit>
#include <cmath>

#include "common/util/bytes.hpp"

namespace tb::emu::radio {
namespace {

template <typename T>
void put(std::vector<std::uint8_t>& out, T v) {
  for (int shift = 8 * (static_cast<int>(sizeof(T)) - 1); shift >= 0; shift -= 8)
    out.push_back(static_cast<std::uint8_t>(static_cast<std::uint64_t>(v) >> shift));
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
  ByteReader r(bytes);
  std::array<std::uint8_t, 4> magic{};
  if (!r.read(magic))
    return U{FederationError::kTooShort};
  const auto version = r.be<std::uint8_t>();
  const auto kind = r.be<std::uint8_t>();
  const std::size_t name_size = r.be<std::uint8_t>();
  if (!r.ok())
    return U{FederationError::kTooShort};
  if (magic != kFederationMagic)
    return U{FederationError::kBadMagic};
  if (version != kFederationVersion)
    return U{FederationError::kUnsupportedVersion};
  FederationDatagram d;
  if (kind == static_cast<std::uint8_t>(FederationKind::kFrame))
    d.kind = FederationKind::kFrame;
  else if (kind == static_cast<std::uint8_t>(FederationKind::kHeartbeat))
    d.kind = FederationKind::kHeartbeat;
  else
    return U{FederationError::kUnknownKind};
  if (name_size == 0 || name_size > kMaxFederationNodeName || name_size > r.remaining())
    return U{FederationError::kBadNodeName};
  const auto name = r.rest().first(name_size);
  d.node = std::string_view(reinterpret_cast<const char*>(name.data()), name.size());
  r.skip(name_size);
  if (d.kind == FederationKind::kHeartbeat) {
    d.tx_unix_ns = r.be<std::int64_t>();
    if (!r.ok())
      return U{FederationError::kTruncated};
    if (r.remaining() != 0)
      return U{FederationError::kTrailingBytes};
    return d;
  }
  d.sender = r.be<std::uint32_t>();
  d.has_position = (r.be<std::uint8_t>() & 1) != 0;  // other flag bits: ignored
  r.skip(1);                                         // reserved: ignored
  const std::size_t frame_size = r.be<std::uint16_t>();
  d.tx_unix_ns = r.be<std::int64_t>();
  for (double& v : d.position)
    v = r.be<double>();
  if (!r.ok())
    return U{FederationError::kTruncated};
  if (d.has_position) {
    for (const double v : d.position)
      if (!std::isfinite(v))
        return U{FederationError::kBadPosition};
  } else {
    d.position = {};
  }
  if (frame_size > kMaxFederatedFrame || frame_size != r.remaining())
    return U{FederationError::kBadFrameLength};
  d.frame = r.rest();
  return d;
}

}  // namespace tb::emu::radio
