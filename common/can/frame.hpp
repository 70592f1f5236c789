#pragma once
/// @file A CAN (or CAN FD) frame as Linux SocketCAN and cannelloni carry it.

#include <algorithm>
#include <array>
#include <cstdint>
#include <span>

namespace tb::can {

/// Linux <linux/can.h> can_id flags; cannelloni carries can_id with these flags unchanged.
inline constexpr std::uint32_t kEffFlag = 0x80000000u;  ///< 29-bit identifier
inline constexpr std::uint32_t kRtrFlag = 0x40000000u;  ///< remote transmission request
inline constexpr std::uint32_t kErrFlag = 0x20000000u;  ///< error frame
inline constexpr std::uint32_t kSffMask = 0x000007FFu;
inline constexpr std::uint32_t kEffMask = 0x1FFFFFFFu;
inline constexpr std::size_t kMaxClassicLen = 8;
inline constexpr std::size_t kMaxFdLen = 64;

struct CanFrame {
  std::uint32_t can_id = 0;   ///< identifier with the Linux flags above
  std::uint8_t len = 0;       ///< payload bytes: 0..8, or 0..64 for CAN FD
  bool fd = false;            ///< CAN FD frame
  std::uint8_t fd_flags = 0;  ///< CAN FD flags (BRS, ESI), only when fd
  std::array<std::uint8_t, kMaxFdLen> data{};

  bool extended() const { return (can_id & kEffFlag) != 0; }
  bool remote() const { return (can_id & kRtrFlag) != 0; }
  /// The identifier without flags.
  std::uint32_t id() const { return can_id & (extended() ? kEffMask : kSffMask); }
  std::span<const std::uint8_t> payload() const { return {data.data(), len}; }
  std::span<std::uint8_t> payload() { return {data.data(), len}; }

  bool operator==(const CanFrame& o) const {
    return can_id == o.can_id && len == o.len && fd == o.fd && fd_flags == o.fd_flags &&
           std::equal(data.begin(), data.begin() + len, o.data.begin());
  }
};

/// A classic data frame with identifier @p id (extended when it does not fit in 11 bits).
inline CanFrame make_frame(std::uint32_t id, std::span<const std::uint8_t> bytes,
                           bool extended = false) {
  CanFrame f;
  f.can_id = (extended || id > kSffMask) ? ((id & kEffMask) | kEffFlag) : id;
  f.len = static_cast<std::uint8_t>(std::min(bytes.size(), kMaxClassicLen));
  std::copy_n(bytes.begin(), f.len, f.data.begin());
  return f;
}

}  // namespace tb::can
