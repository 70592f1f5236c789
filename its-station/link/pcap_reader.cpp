#include "its-station/link/pcap_reader.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <optional>

#include "common/util/bytes.hpp"

namespace tb::its::link {

namespace {

constexpr std::uint32_t kLinkTypeEthernet = 1;
constexpr std::size_t kEthernetHeader = 14;
// pcapng block types (draft-ietf-opsawg-pcapng).
constexpr std::uint32_t kSectionHeaderBlock = 0x0A0D0D0A;
constexpr std::uint32_t kInterfaceDescriptionBlock = 1;
constexpr std::uint32_t kSimplePacketBlock = 3;
constexpr std::uint32_t kEnhancedPacketBlock = 6;
constexpr std::uint32_t kByteOrderMagic = 0x1A2B3C4D;

std::string at(std::size_t offset) {
  return " at byte " + std::to_string(offset);
}

/// Reads unsigned integers in the byte order a capture declared.
struct Reader {
  std::span<const std::uint8_t> bytes;
  bool little = true;

  std::uint32_t u32(std::size_t offset) const {
    ByteReader r{bytes.subspan(offset, 4)};
    return little ? r.le<std::uint32_t>() : r.be<std::uint32_t>();
  }
  std::uint16_t u16(std::size_t offset) const {
    ByteReader r{bytes.subspan(offset, 2)};
    return little ? r.le<std::uint16_t>() : r.be<std::uint16_t>();
  }
};

/// Adds the frame of @p data (an Ethernet II frame) unless it is too short to have a header.
void add_frame(std::vector<CapturedFrame>& out, clock::WallTime time,
               std::span<const std::uint8_t> data) {
  if (data.size() < kEthernetHeader)
    return;
  CapturedFrame f;
  f.time = time;
  std::copy_n(data.begin(), 6, f.destination.begin());
  std::copy_n(data.begin() + 6, 6, f.source.begin());
  f.ethertype = static_cast<std::uint16_t>((data[12] << 8) | data[13]);
  f.payload.assign(data.begin() + kEthernetHeader, data.end());
  out.push_back(std::move(f));
}

clock::WallTime wall_from_ns(std::int64_t ns) {
  return clock::WallTime{
      std::chrono::duration_cast<clock::WallClock::duration>(std::chrono::nanoseconds{ns})};
}

Expected<std::vector<CapturedFrame>, std::string> parse_classic(std::span<const std::uint8_t> b,
                                                                bool little, bool nanoseconds) {
  const Reader r{b, little};
  if (b.size() < 24)
    return Unexpected{std::string{"pcap: file header truncated"}};
  if (r.u32(20) != kLinkTypeEthernet)
    return Unexpected{"pcap: link type " + std::to_string(r.u32(20)) + " is not Ethernet (1)"};
  std::vector<CapturedFrame> out;
  std::size_t pos = 24;
  while (pos < b.size()) {
    if (b.size() - pos < 16)
      return Unexpected{"pcap: record header truncated" + at(pos)};
    const std::uint32_t sec = r.u32(pos);
    const std::uint32_t frac = r.u32(pos + 4);
    const std::uint32_t captured = r.u32(pos + 8);
    if (captured > b.size() - pos - 16)
      return Unexpected{"pcap: record of " + std::to_string(captured) + " bytes truncated" +
                        at(pos)};
    const std::int64_t ns =
        std::int64_t{sec} * 1'000'000'000 + std::int64_t{frac} * (nanoseconds ? 1 : 1000);
    add_frame(out, wall_from_ns(ns), b.subspan(pos + 16, captured));
    pos += 16 + captured;
  }
  return out;
}

/// Timestamp units per second of an interface, from its if_tsresol option (default 10^6).
std::optional<std::uint64_t> units_per_second(std::uint8_t tsresol) {
  const unsigned exponent = tsresol & 0x7f;
  if ((tsresol & 0x80) != 0)
    return exponent < 63 ? std::optional<std::uint64_t>{std::uint64_t{1} << exponent}
                         : std::nullopt;
  if (exponent > 18)
    return std::nullopt;
  std::uint64_t u = 1;
  for (unsigned i = 0; i < exponent; ++i)
    u *= 10;
  return u;
}

struct Interface {
  bool ethernet = false;
  std::uint64_t units = 1'000'000;
};

Expected<std::vector<CapturedFrame>, std::string> parse_pcapng(std::span<const std::uint8_t> b) {
  std::vector<CapturedFrame> out;
  std::vector<Interface> interfaces;
  Reader r{b, true};
  std::size_t pos = 0;
  while (pos < b.size()) {
    if (b.size() - pos < 12)
      return Unexpected{"pcapng: block header truncated" + at(pos)};
    std::uint32_t type = r.u32(pos);
    if (type == kSectionHeaderBlock) {
      // A new section may change the byte order; its interfaces start afresh.
      if (b.size() - pos < 28)
        return Unexpected{"pcapng: section header truncated" + at(pos)};
      const std::uint32_t magic = r.u32(pos + 8);
      if (magic == kByteOrderMagic) {
        // already right
      } else if (Reader{b, !r.little}.u32(pos + 8) == kByteOrderMagic) {
        r.little = !r.little;
      } else {
        return Unexpected{"pcapng: bad byte-order magic" + at(pos + 8)};
      }
      interfaces.clear();
    }
    const std::uint32_t length = r.u32(pos + 4);
    if (length < 12 || length % 4 != 0 || length > b.size() - pos)
      return Unexpected{"pcapng: block length " + std::to_string(length) + " invalid" + at(pos)};
    const auto body = b.subspan(pos + 8, length - 12);
    if (type == kInterfaceDescriptionBlock) {
      if (body.size() < 8)
        return Unexpected{"pcapng: interface description truncated" + at(pos)};
      Interface itf;
      itf.ethernet = r.u16(pos + 8) == kLinkTypeEthernet;
      // Options: code, length, value padded to 4; if_tsresol (9) sets the time unit.
      std::size_t o = 8;
      while (body.size() - o >= 4) {
        const Reader br{body, r.little};
        const std::uint16_t code = br.u16(o);
        const std::uint16_t len = br.u16(o + 2);
        if (code == 0 || std::size_t{len} > body.size() - o - 4)
          break;
        if (code == 9 && len == 1) {
          const auto units = units_per_second(body[o + 4]);
          if (!units)
            return Unexpected{"pcapng: if_tsresol out of range" + at(pos + 8 + o)};
          itf.units = *units;
        }
        o += 4 + ((std::size_t{len} + 3) & ~std::size_t{3});
      }
      interfaces.push_back(itf);
    } else if (type == kEnhancedPacketBlock) {
      if (body.size() < 20)
        return Unexpected{"pcapng: enhanced packet block truncated" + at(pos)};
      const std::uint32_t id = r.u32(pos + 8);
      if (id >= interfaces.size())
        return Unexpected{"pcapng: packet names interface " + std::to_string(id) +
                          ", which is not described" + at(pos)};
      const std::uint64_t ts =
          (std::uint64_t{r.u32(pos + 12)} << 32) | std::uint64_t{r.u32(pos + 16)};
      const std::uint32_t captured = r.u32(pos + 20);
      if (captured > body.size() - 20)
        return Unexpected{"pcapng: packet of " + std::to_string(captured) +
                          " bytes overruns its block" + at(pos)};
      const Interface& itf = interfaces[id];
      if (itf.ethernet) {
        const std::uint64_t s = ts / itf.units;
        const std::uint64_t rest = ts % itf.units;
        const auto ns = static_cast<std::int64_t>(
            s * 1'000'000'000 + static_cast<std::uint64_t>(static_cast<long double>(rest) * 1e9L /
                                                           static_cast<long double>(itf.units)));
        add_frame(out, wall_from_ns(ns), body.subspan(20, captured));
      }
    } else if (type == kSimplePacketBlock) {
      // No timestamp and no interface id: interface 0, time unknown (the epoch).
      if (body.size() < 4)
        return Unexpected{"pcapng: simple packet block truncated" + at(pos)};
      if (interfaces.empty())
        return Unexpected{"pcapng: simple packet before any interface" + at(pos)};
      const std::size_t captured = std::min<std::size_t>(r.u32(pos + 8), body.size() - 4);
      if (interfaces[0].ethernet)
        add_frame(out, clock::WallTime{}, body.subspan(4, captured));
    }
    pos += length;
  }
  return out;
}

}  // namespace

Expected<std::vector<CapturedFrame>, std::string> parse_capture(
    std::span<const std::uint8_t> bytes) {
  if (bytes.size() < 4)
    return Unexpected{std::string{"capture: shorter than any file header"}};
  const Reader le{bytes, true};
  const Reader be{bytes, false};
  if (le.u32(0) == kSectionHeaderBlock)
    return parse_pcapng(bytes);
  for (const bool little : {true, false}) {
    const std::uint32_t magic = little ? le.u32(0) : be.u32(0);
    if (magic == 0xa1b2c3d4)
      return parse_classic(bytes, little, false);
    if (magic == 0xa1b23c4d)
      return parse_classic(bytes, little, true);
  }
  return Unexpected{std::string{"capture: neither pcap nor pcapng (unknown magic number)"}};
}

Expected<std::vector<CapturedFrame>, std::string> read_capture(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    return Unexpected{"capture '" + path + "': cannot open: " + std::strerror(errno)};
  const std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(in),
                                        std::istreambuf_iterator<char>()};
  auto frames = parse_capture(bytes);
  if (!frames)
    return Unexpected{"capture '" + path + "': " + frames.error()};
  return frames;
}

}  // namespace tb::its::link
