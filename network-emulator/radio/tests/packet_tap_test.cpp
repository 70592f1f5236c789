// The TPACKET_V3 block walk of PacketTap on hand-laid blocks: frames, interfaces and kernel
// times come out as laid down, and a block whose offsets point outside it stops the walk.

#include <linux/if_packet.h>

#include <cstring>
#include <optional>
#include <vector>

#include <gtest/gtest.h>

#include "network-emulator/radio/packet_tap.hpp"

namespace tb::emu::radio {
namespace {

constexpr std::size_t kBlock = 4096;

/// Lays frames into a block as the kernel does: block descriptor, then per frame a
/// tpacket3_hdr, the sockaddr_ll behind it and the frame at tp_mac.
class BlockBuilder {
 public:
  BlockBuilder() : block_(kBlock, 0) { next_ = TPACKET_ALIGN(sizeof(tpacket_block_desc)); }
  /// Returns the offset of the frame's header.
  std::size_t add(int ifindex, const std::vector<std::uint8_t>& bytes, std::uint32_t sec,
                  std::uint32_t nsec) {
    const std::size_t at = next_;
    tpacket3_hdr h{};
    h.tp_sec = sec;
    h.tp_nsec = nsec;
    h.tp_snaplen = static_cast<std::uint32_t>(bytes.size());
    h.tp_len = static_cast<std::uint32_t>(bytes.size());
    h.tp_mac =
        static_cast<std::uint16_t>(TPACKET_ALIGN(sizeof(tpacket3_hdr)) + sizeof(sockaddr_ll));
    const std::size_t size = TPACKET_ALIGN(h.tp_mac + bytes.size());
    sockaddr_ll sll{};
    sll.sll_ifindex = ifindex;
    std::memcpy(&block_[at + TPACKET_ALIGN(sizeof(tpacket3_hdr))], &sll, sizeof sll);
    std::memcpy(&block_[at + h.tp_mac], bytes.data(), bytes.size());
    if (last_)  // the previous frame points to this one
      header(*last_).tp_next_offset = static_cast<std::uint32_t>(at - *last_);
    std::memcpy(&block_[at], &h, sizeof h);
    last_ = at;
    next_ = at + size;
    tpacket_block_desc d{};
    std::memcpy(&d, block_.data(), sizeof d);
    d.hdr.bh1.num_pkts++;
    d.hdr.bh1.offset_to_first_pkt = TPACKET_ALIGN(sizeof(tpacket_block_desc));
    std::memcpy(block_.data(), &d, sizeof d);
    return at;
  }
  tpacket3_hdr& header(std::size_t at) { return *reinterpret_cast<tpacket3_hdr*>(&block_[at]); }
  const std::uint8_t* data() const { return block_.data(); }

 private:
  std::vector<std::uint8_t> block_;
  std::size_t next_;
  std::optional<std::size_t> last_;
};

struct Seen {
  int ifindex;
  std::vector<std::uint8_t> bytes;
  std::int64_t unix_ns;
};

std::vector<Seen> walk(const BlockBuilder& b, std::size_t* count = nullptr) {
  std::vector<Seen> seen;
  const std::size_t n = for_each_frame_in_block(b.data(), kBlock, [&](const TappedFrame& f) {
    seen.push_back({f.ifindex, {f.bytes.begin(), f.bytes.end()}, f.unix_ns});
  });
  if (count)
    *count = n;
  return seen;
}

TEST(PacketTapBlock, GivesEveryFrameWithItsInterfaceAndKernelTime) {
  BlockBuilder b;
  b.add(7, {1, 2, 3}, 1'700'000'000, 5);
  b.add(9, std::vector<std::uint8_t>(200, 0xab), 1'700'000'001, 999'999'999);
  b.add(7, {4}, 1'700'000'002, 0);
  std::size_t n = 0;
  const auto seen = walk(b, &n);
  ASSERT_EQ(n, 3u);
  ASSERT_EQ(seen.size(), 3u);
  EXPECT_EQ(seen[0].ifindex, 7);
  EXPECT_EQ(seen[0].bytes, (std::vector<std::uint8_t>{1, 2, 3}));
  EXPECT_EQ(seen[0].unix_ns, 1'700'000'000'000'000'005);
  EXPECT_EQ(seen[1].ifindex, 9);
  EXPECT_EQ(seen[1].bytes.size(), 200u);
  EXPECT_EQ(seen[1].unix_ns, 1'700'000'001'999'999'999);
  EXPECT_EQ(seen[2].bytes, (std::vector<std::uint8_t>{4}));
}

TEST(PacketTapBlock, AnEmptyBlockHasNoFrames) {
  BlockBuilder b;
  EXPECT_TRUE(walk(b).empty());
}

TEST(PacketTapBlock, AFrameReachingPastTheBlockStopsTheWalk) {
  BlockBuilder b;
  b.add(1, {1}, 1, 0);
  const std::size_t second = b.add(2, {2}, 2, 0);
  b.add(3, {3}, 3, 0);
  b.header(second).tp_snaplen = kBlock;  // would read past the end of the block
  const auto seen = walk(b);
  ASSERT_EQ(seen.size(), 1u);
  EXPECT_EQ(seen[0].ifindex, 1);
}

TEST(PacketTapBlock, AnOffsetPastTheBlockStopsTheWalk) {
  BlockBuilder b;
  const std::size_t first = b.add(1, {1}, 1, 0);
  b.add(2, {2}, 2, 0);
  b.header(first).tp_next_offset = kBlock;  // the next frame would start outside the block
  const auto seen = walk(b);
  ASSERT_EQ(seen.size(), 1u);
}

}  // namespace
}  // namespace tb::emu::radio
