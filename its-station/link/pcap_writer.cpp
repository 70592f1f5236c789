#include "its-station/link/pcap_writer.hpp"

#include <array>
#include <cerrno>
#include <cstring>
#include <vector>

#include "common/util/bytes.hpp"

namespace tb::its::link {

namespace {
constexpr std::uint32_t kPcapMagic = 0xa1b2c3d4;  // microsecond timestamps
constexpr std::uint32_t kLinkTypeEthernet = 1;
constexpr std::uint32_t kSnapLength = 65535;
}  // namespace

Expected<PcapWriter, std::string> PcapWriter::create(const std::string& path) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out)
    return Unexpected{"pcap: cannot create '" + path + "': " + std::strerror(errno)};
  // Little-endian throughout; readers tell the byte order from the magic number.
  std::array<std::uint8_t, 24> header{};
  ByteWriter w{header};
  w.le<std::uint32_t>(kPcapMagic);
  w.le<std::uint16_t>(2);  // version 2.4
  w.le<std::uint16_t>(4);
  w.le<std::int32_t>(0);   // GMT offset
  w.le<std::uint32_t>(0);  // timestamp accuracy
  w.le<std::uint32_t>(kSnapLength);
  w.le<std::uint32_t>(kLinkTypeEthernet);
  out.write(reinterpret_cast<const char*>(header.data()), header.size());
  if (!out)
    return Unexpected{"pcap: cannot write '" + path + "': " + std::strerror(errno)};
  return PcapWriter{std::move(out)};
}

bool PcapWriter::write(clock::WallTime time, const MacAddress& destination,
                       const MacAddress& source, std::uint16_t ethertype,
                       std::span<const std::uint8_t> payload) {
  const std::size_t frame_length = 14 + payload.size();
  if (frame_length > kSnapLength)
    return false;
  const std::int64_t us = clock::to_unix_ns(time) / 1000;
  std::vector<std::uint8_t> record(16 + frame_length);
  ByteWriter w{record};
  w.le<std::uint32_t>(static_cast<std::uint32_t>(us / 1'000'000));
  w.le<std::uint32_t>(static_cast<std::uint32_t>(us % 1'000'000));
  w.le<std::uint32_t>(static_cast<std::uint32_t>(frame_length));  // captured
  w.le<std::uint32_t>(static_cast<std::uint32_t>(frame_length));  // on the wire
  w.write(destination);
  w.write(source);
  w.be<std::uint16_t>(ethertype);
  w.write(payload);
  out_.write(reinterpret_cast<const char*>(record.data()),
             static_cast<std::streamsize>(w.position()));
  return static_cast<bool>(out_);
}

bool PcapWriter::flush() {
  out_.flush();
  return static_cast<bool>(out_);
}

}  // namespace tb::its::link
