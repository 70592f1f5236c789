#include "common/can/cannelloni.hpp"

#include "common/util/bytes.hpp"

namespace tb::can {

std::string_view to_string(CannelloniError e) {
  switch (e) {
    case CannelloniError::kTruncatedHeader:
      return "packet shorter than the 5-byte header";
    case CannelloniError::kUnsupportedVersion:
      return "version is not 2";
    case CannelloniError::kNotData:
      return "op code is not DATA";
    case CannelloniError::kTruncatedFrame:
      return "frame runs past the end of the packet";
    case CannelloniError::kBadLength:
      return "frame length above 8 (CAN) or 64 (CAN FD)";
    case CannelloniError::kTrailingBytes:
      return "bytes after the last frame";
  }
  return "unknown cannelloni error";
}

namespace {
std::size_t frame_size(const CanFrame& f) {
  return 4 + 1 + (f.fd ? 1 : 0) + (f.remote() ? 0 : f.len);
}
}  // namespace

std::size_t cannelloni_size(std::span<const CanFrame> frames) {
  std::size_t n = kCannelloniHeaderSize;
  for (const CanFrame& f : frames)
    n += frame_size(f);
  return n;
}

std::size_t encode_cannelloni(std::uint8_t sequence, std::span<const CanFrame> frames,
                              std::span<std::uint8_t> out) {
  if (frames.size() > 0xFFFF || cannelloni_size(frames) > out.size())
    return 0;
  ByteWriter w(out);
  w.be<std::uint8_t>(kCannelloniVersion);
  w.be<std::uint8_t>(kCannelloniOpData);
  w.be<std::uint8_t>(sequence);
  w.be<std::uint16_t>(static_cast<std::uint16_t>(frames.size()));
  for (const CanFrame& f : frames) {
    const std::uint8_t len = std::min<std::uint8_t>(f.len, f.fd ? kMaxFdLen : kMaxClassicLen);
    w.be<std::uint32_t>(f.can_id);
    w.be<std::uint8_t>(f.fd ? static_cast<std::uint8_t>(len | kCannelloniFdFlag) : len);
    if (f.fd)
      w.be<std::uint8_t>(f.fd_flags);
    // cannelloni sends no data bytes for remote frames, although they carry a length.
    if (!f.remote())
      w.write({f.data.data(), len});
  }
  return w.ok() ? w.position() : 0;
}

std::vector<std::uint8_t> encode_cannelloni(std::uint8_t sequence,
                                            std::span<const CanFrame> frames) {
  std::vector<std::uint8_t> out(cannelloni_size(frames));
  out.resize(encode_cannelloni(sequence, frames, out));
  return out;
}

Expected<CannelloniPacket, CannelloniError> decode_cannelloni(std::span<const std::uint8_t> bytes) {
  ByteReader r(bytes);
  const auto version = r.be<std::uint8_t>();
  const auto op = r.be<std::uint8_t>();
  const auto sequence = r.be<std::uint8_t>();
  const auto count = r.be<std::uint16_t>();
  if (!r.ok())
    return Unexpected{CannelloniError::kTruncatedHeader};
  if (version != kCannelloniVersion)
    return Unexpected{CannelloniError::kUnsupportedVersion};
  if (op != kCannelloniOpData)
    return Unexpected{CannelloniError::kNotData};

  CannelloniPacket p;
  p.sequence = sequence;
  // Each frame takes at least 5 bytes: a count beyond that is a lie, not a reason to allocate.
  if (count > r.remaining() / 5)
    return Unexpected{CannelloniError::kTruncatedFrame};
  p.frames.reserve(count);
  for (unsigned i = 0; i < count; ++i) {
    CanFrame f;
    f.can_id = r.be<std::uint32_t>();
    const auto len_byte = r.be<std::uint8_t>();
    f.fd = (len_byte & kCannelloniFdFlag) != 0;
    f.len = static_cast<std::uint8_t>(len_byte & ~kCannelloniFdFlag);
    if (f.fd)
      f.fd_flags = r.be<std::uint8_t>();
    if (!r.ok())
      return Unexpected{CannelloniError::kTruncatedFrame};
    if (f.len > (f.fd ? kMaxFdLen : kMaxClassicLen))
      return Unexpected{CannelloniError::kBadLength};
    if (!f.remote() && !r.read({f.data.data(), f.len}))
      return Unexpected{CannelloniError::kTruncatedFrame};
    p.frames.push_back(f);
  }
  if (r.remaining() != 0)
    return Unexpected{CannelloniError::kTrailingBytes};
  return p;
}

}  // namespace tb::can
