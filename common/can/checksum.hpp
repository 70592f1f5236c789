#pragma once
/// @file The checksum of the project's CAN messages (common/can/vehicle.dbc).

#include <cstdint>
#include <span>

namespace tb::can {

/// CRC-8 SAE J1850: polynomial 0x1D, initial value 0xFF, final XOR 0xFF, no reflection
/// (check value over "123456789" = 0x4B). The same CRC that AUTOSAR E2E profile 1 uses.
std::uint8_t crc8_sae_j1850(std::span<const std::uint8_t> bytes);

}  // namespace tb::can
