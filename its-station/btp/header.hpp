#pragma once
/// @file BTP headers (EN 302 636-5-1 V2.2.1 clause 7): BTP-A for interactive transport (with a
/// source port), BTP-B for non-interactive transport (with destination port info).

#include <cstdint>
#include <span>
#include <string>

#include "common/util/bytes.hpp"
#include "common/util/expected.hpp"

namespace tb::its::btp {

/// Well-known BTP-B ports (EN 302 636-5-1 Annex B / TS 103 248).
inline constexpr std::uint16_t kPortCam = 2001;
inline constexpr std::uint16_t kPortDenm = 2002;
inline constexpr std::uint16_t kPortMapem = 2003;  ///< TS 103 301 (issue 34)
inline constexpr std::uint16_t kPortSpatem = 2004;

inline constexpr std::size_t kHeaderSize = 4;

struct HeaderA {
  std::uint16_t destination_port = 0;
  std::uint16_t source_port = 0;
  bool operator==(const HeaderA&) const = default;
};

struct HeaderB {
  std::uint16_t destination_port = 0;
  std::uint16_t destination_port_info = 0;
  bool operator==(const HeaderB&) const = default;
};

enum class ParseError { kTruncatedHeader };
std::string to_string(ParseError e);

/// Both headers are two big-endian 16-bit fields; the payload follows.
Expected<HeaderA, ParseError> parse_header_a(std::span<const std::uint8_t> bytes);
Expected<HeaderB, ParseError> parse_header_b(std::span<const std::uint8_t> bytes);
void write_header(ByteWriter& w, const HeaderA& h);
void write_header(ByteWriter& w, const HeaderB& h);

}  // namespace tb::its::btp
