#include "network-emulator/radio/packet_tap.hpp"

#include <arpa/inet.h>
#include <linux/filter.h>
#include <net/ethernet.h>
#include <sys/mman.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>
#include <system_error>
#include <vector>

namespace tb::emu::radio {

namespace {
[[noreturn]] void fail(int err, const std::string& what) {
  throw std::system_error(err, std::generic_category(), "AF_PACKET: " + what);
}

std::vector<sock_filter> filter_program(std::uint16_t ethertype, int exclude_ifindex) {
  std::vector<sock_filter> p;
  std::vector<std::size_t> to_drop;  // conditional jumps that go to the final "drop"
  if (ethertype != kEthertypeAll) {
    p.push_back(BPF_STMT(BPF_LD | BPF_H | BPF_ABS, 12));  // the Ethernet header's type field
    to_drop.push_back(p.size());
    p.push_back(BPF_JUMP(BPF_JMP | BPF_JEQ | BPF_K, ethertype, 0, 0));  // jf → drop
  }
  if (exclude_ifindex > 0) {
    p.push_back(BPF_STMT(BPF_LD | BPF_W | BPF_ABS,
                         static_cast<std::uint32_t>(SKF_AD_OFF + SKF_AD_IFINDEX)));
    p.push_back(BPF_JUMP(BPF_JMP | BPF_JEQ | BPF_K, static_cast<std::uint32_t>(exclude_ifindex), 0,
                         1));  // jt → drop (patched below), jf → accept
  }
  p.push_back(BPF_STMT(BPF_RET | BPF_K, 0xFFFFFFFFu));  // accept, as much as the ring takes
  p.push_back(BPF_STMT(BPF_RET | BPF_K, 0));            // drop
  const std::size_t drop = p.size() - 1;
  for (const std::size_t i : to_drop)
    p[i].jf = static_cast<std::uint8_t>(drop - i - 1);
  if (exclude_ifindex > 0) {
    const std::size_t i = drop - 2;  // the ifindex comparison
    p[i].jt = static_cast<std::uint8_t>(drop - i - 1);
    p[i].jf = 0;
  }
  return p;
}
}  // namespace

void attach_ethertype_filter(int fd, std::uint16_t ethertype, int exclude_ifindex) {
  auto program = filter_program(ethertype, exclude_ifindex);
  sock_fprog fprog{static_cast<unsigned short>(program.size()), program.data()};
  if (::setsockopt(fd, SOL_SOCKET, SO_ATTACH_FILTER, &fprog, sizeof fprog) != 0)
    fail(errno, "SO_ATTACH_FILTER");
}

std::size_t for_each_frame_in_block(const std::uint8_t* block, std::size_t block_size,
                                    const std::function<void(const TappedFrame&)>& f) {
  if (block_size < sizeof(tpacket_block_desc))
    return 0;
  tpacket_block_desc desc;
  std::memcpy(&desc, block, sizeof desc);
  const std::uint32_t count = desc.hdr.bh1.num_pkts;
  std::size_t offset = desc.hdr.bh1.offset_to_first_pkt;
  std::size_t seen = 0;
  for (std::uint32_t i = 0; i < count; ++i) {
    const std::size_t sll_offset = offset + TPACKET_ALIGN(sizeof(tpacket3_hdr));
    if (offset < sizeof desc || sll_offset + sizeof(sockaddr_ll) > block_size)
      break;
    tpacket3_hdr h;
    std::memcpy(&h, block + offset, sizeof h);
    sockaddr_ll sll;
    std::memcpy(&sll, block + sll_offset, sizeof sll);
    if (h.tp_mac > block_size - offset || h.tp_snaplen > block_size - offset - h.tp_mac)
      break;
    TappedFrame frame;
    frame.ifindex = sll.sll_ifindex;
    frame.bytes = {block + offset + h.tp_mac, h.tp_snaplen};
    frame.wire_length = h.tp_len;
    frame.unix_ns = static_cast<std::int64_t>(h.tp_sec) * 1'000'000'000 + h.tp_nsec;
    f(frame);
    ++seen;
    if (h.tp_next_offset == 0)
      break;
    offset += h.tp_next_offset;
  }
  return seen;
}

PacketTap::PacketTap(std::uint16_t ethertype, int exclude_ifindex, std::size_t block_size,
                     std::size_t block_count, std::uint32_t snap)
    : block_size_(block_size), block_count_(block_count) {
  // Protocol 0: no frame comes in before the filter and the ring are in place and bind() names
  // the protocol.
  fd_ = ::socket(AF_PACKET, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd_ < 0)
    fail(errno, "AF_PACKET socket (needs CAP_NET_RAW)");
  try {
    int one = 1;
    // Frames this host sends (the bridge's copies out of the other ports among them) are no
    // frames on the air.
    if (::setsockopt(fd_, SOL_PACKET, PACKET_IGNORE_OUTGOING, &one, sizeof one) != 0)
      fail(errno, "PACKET_IGNORE_OUTGOING (Linux >= 4.20)");
    attach_ethertype_filter(fd_, ethertype, exclude_ifindex);
    int version = TPACKET_V3;
    if (::setsockopt(fd_, SOL_PACKET, PACKET_VERSION, &version, sizeof version) != 0)
      fail(errno, "PACKET_VERSION TPACKET_V3");
    // Room for a frame of `snap` bytes behind the ring's own headers.
    const std::size_t frame_size =
        TPACKET_ALIGN(TPACKET_ALIGN(sizeof(tpacket3_hdr)) + sizeof(sockaddr_ll) + 16 + snap);
    tpacket_req3 req{};
    req.tp_block_size = static_cast<unsigned>(block_size_);
    req.tp_block_nr = static_cast<unsigned>(block_count_);
    req.tp_frame_size = static_cast<unsigned>(frame_size);
    req.tp_frame_nr = static_cast<unsigned>(block_size_ / frame_size * block_count_);
    req.tp_retire_blk_tov = kBlockTimeoutMs;
    if (::setsockopt(fd_, SOL_PACKET, PACKET_RX_RING, &req, sizeof req) != 0)
      fail(errno, "PACKET_RX_RING of " + std::to_string(block_count_) + " blocks of " +
                      std::to_string(block_size_) + " bytes");
    void* ring =
        ::mmap(nullptr, block_size_ * block_count_, PROT_READ | PROT_WRITE, MAP_SHARED, fd_, 0);
    if (ring == MAP_FAILED)
      fail(errno, "mmap of the receive ring");
    ring_ = static_cast<std::uint8_t*>(ring);
    sockaddr_ll addr{};
    addr.sll_family = AF_PACKET;
    addr.sll_protocol = htons(ETH_P_ALL);  // the filter picks the ethertype
    addr.sll_ifindex = 0;                  // every interface of this namespace
    if (::bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0)
      fail(errno, "bind");
  } catch (...) {
    if (ring_)
      ::munmap(ring_, block_size_ * block_count_);
    ::close(fd_);
    throw;
  }
}

PacketTap::~PacketTap() {
  if (ring_)
    ::munmap(ring_, block_size_ * block_count_);
  if (fd_ >= 0)
    ::close(fd_);
}

std::size_t PacketTap::drain(const std::function<void(const TappedFrame&)>& f) {
  std::size_t frames = 0;
  // At most one round of the ring: blocks the kernel finishes meanwhile wake the reader again.
  for (std::size_t i = 0; i < block_count_; ++i) {
    std::uint8_t* block = ring_ + next_ * block_size_;
    auto* desc = reinterpret_cast<tpacket_block_desc*>(block);
    if (!(__atomic_load_n(&desc->hdr.bh1.block_status, __ATOMIC_ACQUIRE) & TP_STATUS_USER))
      break;
    frames += for_each_frame_in_block(block, block_size_, f);
    __atomic_store_n(&desc->hdr.bh1.block_status, TP_STATUS_KERNEL, __ATOMIC_RELEASE);
    next_ = (next_ + 1) % block_count_;
  }
  return frames;
}

std::uint64_t PacketTap::drops() {
  // Reading the statistics resets them in the kernel: they are added up here.
  tpacket_stats_v3 s{};
  socklen_t len = sizeof s;
  if (::getsockopt(fd_, SOL_PACKET, PACKET_STATISTICS, &s, &len) == 0)
    drops_ += s.tp_drops;
  return drops_;
}

}  // namespace tb::emu::radio
