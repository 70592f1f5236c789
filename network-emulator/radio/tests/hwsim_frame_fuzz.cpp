// libFuzzer target: any bytes the kernel could hand the hwsim medium as a netlink message must
// be parsed or rejected by hwsim::parse_frame without reading outside the message.

#include <netlink/msg.h>

#include <cstdint>
#include <cstring>
#include <vector>

#include "network-emulator/radio/hwsim.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < sizeof(nlmsghdr) || size > 65536)
    return 0;
  // The kernel's length field always matches what arrived; keep that invariant, fuzz the rest.
  std::vector<std::uint8_t> buf(data, data + size);
  auto* hdr = reinterpret_cast<nlmsghdr*>(buf.data());
  hdr->nlmsg_len = static_cast<std::uint32_t>(size);
  nl_msg* msg = nlmsg_convert(hdr);
  if (!msg)
    return 0;
  auto parsed = tb::emu::radio::hwsim::parse_frame(msg);
  if (parsed) {
    // Touch what was copied so that a bad length would show up under ASan.
    std::uint8_t x = 0;
    for (auto b : parsed->frame)
      x ^= b;
    for (auto b : parsed->tx_info)
      x ^= b;
    volatile std::uint8_t sink = x;
    (void)sink;
  } else {
    (void)tb::emu::radio::hwsim::to_string(parsed.error());
  }
  nlmsg_free(msg);
  return 0;
}
