#pragma once
/// @file PacketTap: every frame of one ethertype that comes in on any interface of this
/// network namespace, read from a TPACKET_V3 receive ring that the kernel fills.
///
/// The in-kernel medium (bridge_medium.hpp) forwards frames without the program, which still
/// sees each one for the trace (`medium.rx`) and the per-link statistics, but need not see it
/// at once: the ring hands frames over in blocks, and the kernel wakes the reader when a block
/// is full or kBlockTimeoutMs old. So the program wakes tens of times a second instead of once
/// per frame, and reads no frame with a system call. Each frame carries the kernel's receive
/// time (CLOCK_REALTIME), so reading it late costs the trace nothing.

#include <linux/if_packet.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>

#include "network-emulator/radio/frame_tag.hpp"

namespace tb::emu::radio {

/// One frame out of the ring.
struct TappedFrame {
  int ifindex = 0;                      ///< the interface it came in on
  std::span<const std::uint8_t> bytes;  ///< from the Ethernet header on (may be cut, see snap)
  std::uint32_t wire_length = 0;        ///< its length on the wire
  std::int64_t unix_ns = 0;             ///< when the kernel received it
};

/// Attaches to the AF_PACKET socket @p fd a filter that keeps frames of @p ethertype
/// (kEthertypeAll: every frame) that did not come in on @p exclude_ifindex (0: none). The
/// kernel runs it before a frame is queued, so the host's other traffic costs the reader
/// nothing. @throws std::system_error.
void attach_ethertype_filter(int fd, std::uint16_t ethertype, int exclude_ifindex);

/// Calls @p f for every frame of one block of a TPACKET_V3 ring (@p block, @p block_size bytes
/// as the kernel laid it out). Frames whose header or data would lie outside the block are
/// skipped, and the walk stops there; returns the number of frames handed to @p f.
std::size_t for_each_frame_in_block(const std::uint8_t* block, std::size_t block_size,
                                    const std::function<void(const TappedFrame&)>& f);

class PacketTap {
 public:
  /// Blocks are handed over at the latest this long after their first frame.
  static constexpr unsigned kBlockTimeoutMs = 20;

  /// Taps frames of @p ethertype (kEthertypeAll: every frame) coming in on every interface of
  /// the calling thread's namespace but @p exclude_ifindex (0: none), in a ring of
  /// @p block_count blocks of @p block_size bytes; frames longer than @p snap bytes are cut.
  /// Never sees a frame that this host sends. @throws std::system_error.
  PacketTap(std::uint16_t ethertype, int exclude_ifindex, std::size_t block_size = 1 << 18,
            std::size_t block_count = 32, std::uint32_t snap = 2048);
  ~PacketTap();
  PacketTap(const PacketTap&) = delete;
  PacketTap& operator=(const PacketTap&) = delete;

  /// Readable (poll) when a block is ready.
  int fd() const { return fd_; }
  /// Hands every frame of every block the kernel has finished to @p f and gives the blocks
  /// back; returns the number of frames.
  std::size_t drain(const std::function<void(const TappedFrame&)>& f);
  /// Frames the kernel could not put into the ring because it was full (PACKET_STATISTICS;
  /// cumulative over the tap's life).
  std::uint64_t drops();

 private:
  int fd_ = -1;
  std::uint8_t* ring_ = nullptr;
  std::size_t block_size_, block_count_;
  std::size_t next_ = 0;
  std::uint64_t drops_ = 0;
};

}  // namespace tb::emu::radio
