#pragma once
/// @file cannelloni's UDP wire format (CAN frames over UDP), version 2.
///
/// Big-endian. Header: version (2), op code (DATA = 0), sequence number (u8), frame count
/// (u16). Then per frame: can_id (u32, Linux flags), len (u8; bit 0x80 marks CAN FD and is
/// followed by a flags byte), and len data bytes — none for remote (RTR) frames. The same
/// bytes as cannelloni itself, so that cannelloni can bridge them to a real CAN bus.

#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "common/can/frame.hpp"
#include "common/util/expected.hpp"

namespace tb::can {

inline constexpr std::uint8_t kCannelloniVersion = 2;
inline constexpr std::uint8_t kCannelloniOpData = 0;
inline constexpr std::uint8_t kCannelloniFdFlag = 0x80;
inline constexpr std::size_t kCannelloniHeaderSize = 5;
inline constexpr std::uint16_t kCannelloniDefaultPort = 20000;

enum class CannelloniError {
  kTruncatedHeader,
  kUnsupportedVersion,
  kNotData,
  kTruncatedFrame,
  kBadLength,
  kTrailingBytes,
};
std::string_view to_string(CannelloniError e);

struct CannelloniPacket {
  std::uint8_t sequence = 0;
  std::vector<CanFrame> frames;
};

/// Bytes that @p frames take on the wire, header included.
std::size_t cannelloni_size(std::span<const CanFrame> frames);
/// Writes one packet into @p out; returns the bytes written, or 0 if @p out is too small.
std::size_t encode_cannelloni(std::uint8_t sequence, std::span<const CanFrame> frames,
                              std::span<std::uint8_t> out);
std::vector<std::uint8_t> encode_cannelloni(std::uint8_t sequence,
                                            std::span<const CanFrame> frames);
/// Never reads outside @p bytes.
Expected<CannelloniPacket, CannelloniError> decode_cannelloni(std::span<const std::uint8_t> bytes);

}  // namespace tb::can
