// radio-probe: sends or counts numbered GeoNetworking-ethertype frames on an interface of the
// namespace it runs in (`ip netns exec NS radio-probe ...`). For checking radios by hand and in
// the hwsim VM test (tests/hwsim_vm_test.sh); usage in README.md.

#include <poll.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>

#include "network-emulator/radio/packet_socket.hpp"

namespace radio = tb::emu::radio;

namespace {
constexpr std::size_t kSeqOffset = 14;  // right after the Ethernet header

int send_frames(radio::PacketSocket& s, std::uint32_t count, int interval_ms, int warmup_ms) {
  std::vector<std::uint8_t> f(100, 0);
  std::fill_n(f.begin(), 6, 0xff);
  std::memcpy(f.data() + 6, "\x02\x00\x00\x00\x00\x00", 6);  // the kernel keeps our bytes
  f[12] = 0x89;
  f[13] = 0x47;
  // Frame 0 is a warm-up: a mac80211 OCB receiver drops the first frame from a peer it does not
  // know yet while it adds the peer (ieee80211_ocb_rx_no_sta), so counting starts at 1.
  for (std::uint32_t seq = 0; seq <= count; ++seq) {
    std::memcpy(f.data() + kSeqOffset, &seq, 4);
    if (!s.send(f)) {
      std::perror("radio-probe: send");
      return 1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(seq == 0 ? warmup_ms : interval_ms));
  }
  std::printf("sent %u\n", count);
  return 0;
}

int receive_frames(radio::PacketSocket& s, std::uint32_t count, double timeout_s) {
  std::vector<bool> seen(count + 1, false);
  std::uint32_t got = 0;
  std::array<std::uint8_t, 4096> buf{};
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (got < count && std::chrono::steady_clock::now() < end) {
    pollfd p{s.fd(), POLLIN, 0};
    if (::poll(&p, 1, 100) <= 0)
      continue;
    long n;
    while ((n = s.receive(buf)) > 0) {
      if (static_cast<std::size_t>(n) < kSeqOffset + 4)
        continue;
      std::uint32_t seq;
      std::memcpy(&seq, buf.data() + kSeqOffset, 4);
      if (seq >= 1 && seq <= count && !seen[seq]) {
        seen[seq] = true;
        ++got;
      }
    }
  }
  std::printf("received %u of %u", got, count);
  if (got < count && got > 0) {
    std::printf(", missing:");
    for (std::uint32_t i = 1; i <= count; ++i)
      if (!seen[i])
        std::printf(" %u", i);
  }
  std::printf("\n");
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"radio-probe: send or count numbered 0x8947 frames on an interface"};
  app.require_subcommand(1);
  std::string ifname = "wlan0";
  std::uint32_t count = 100;
  int interval_ms = 2, warmup_ms = 300;
  double timeout_s = 10;
  auto* send = app.add_subcommand("send", "send COUNT frames (after one warm-up frame)");
  auto* recv = app.add_subcommand("recv", "count frames 1..COUNT until all arrived or timeout");
  for (auto* sub : {send, recv}) {
    sub->add_option("interface", ifname, "interface (default wlan0)");
    sub->add_option("--count", count, "frames")->check(CLI::Range(1u, 1'000'000u));
  }
  send->add_option("--interval-ms", interval_ms, "pause between frames")
      ->check(CLI::NonNegativeNumber);
  send->add_option("--warmup-ms", warmup_ms, "pause after the warm-up frame")
      ->check(CLI::NonNegativeNumber);
  recv->add_option("--timeout", timeout_s, "seconds")->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);
  try {
    radio::PacketSocket s(ifname, radio::kEthertypeGeoNetworking, 8 << 20);
    return send->parsed() ? send_frames(s, count, interval_ms, warmup_ms)
                          : receive_frames(s, count, timeout_s);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "radio-probe: %s\n", e.what());
    return 1;
  }
}
