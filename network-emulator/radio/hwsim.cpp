#include "network-emulator/radio/hwsim.hpp"

#include <netlink/attr.h>
#include <netlink/genl/genl.h>
#include <netlink/msg.h>

#include <cstring>

namespace tb::emu::radio::hwsim {

std::string_view to_string(FrameError e) {
  switch (e) {
    case FrameError::kNotAFrame:
      return "not a HWSIM_CMD_FRAME message";
    case FrameError::kMalformed:
      return "malformed attributes";
    case FrameError::kNoTransmitter:
      return "HWSIM_ATTR_ADDR_TRANSMITTER missing or not 6 bytes";
    case FrameError::kNoFrame:
      return "HWSIM_ATTR_FRAME missing or shorter than 2 bytes";
    case FrameError::kNoCookie:
      return "HWSIM_ATTR_COOKIE missing or not 8 bytes";
    case FrameError::kBadTxInfo:
      return "HWSIM_ATTR_TX_INFO not a whole array of up to 4 rates";
    case FrameError::kBadFlags:
      return "HWSIM_ATTR_FLAGS missing or not 4 bytes";
  }
  return "unknown";
}

Expected<TxFrame, FrameError> parse_frame(nl_msg* msg) {
  nlmsghdr* hdr = nlmsg_hdr(msg);
  if (!genlmsg_valid_hdr(hdr, 0))
    return Unexpected{FrameError::kMalformed};
  const auto* g = static_cast<const genlmsghdr*>(nlmsg_data(hdr));
  if (g->cmd != kCmdFrame)
    return Unexpected{FrameError::kNotAFrame};
  nlattr* a[kAttrMax + 1] = {};
  // No policy: each attribute's length is checked below before it is read.
  if (genlmsg_parse(hdr, 0, a, kAttrMax, nullptr) < 0)
    return Unexpected{FrameError::kMalformed};
  TxFrame f;
  if (!a[kAttrAddrTransmitter] || nla_len(a[kAttrAddrTransmitter]) != 6)
    return Unexpected{FrameError::kNoTransmitter};
  std::memcpy(f.transmitter.data(), nla_data(a[kAttrAddrTransmitter]), 6);
  if (!a[kAttrFrame] || nla_len(a[kAttrFrame]) < 2)
    return Unexpected{FrameError::kNoFrame};
  const auto* data = static_cast<const std::uint8_t*>(nla_data(a[kAttrFrame]));
  f.frame.assign(data, data + nla_len(a[kAttrFrame]));
  if (!a[kAttrFlags] || nla_len(a[kAttrFlags]) != 4)
    return Unexpected{FrameError::kBadFlags};
  f.flags = nla_get_u32(a[kAttrFlags]);
  if (!a[kAttrCookie] || nla_len(a[kAttrCookie]) != 8)
    return Unexpected{FrameError::kNoCookie};
  f.cookie = nla_get_u64(a[kAttrCookie]);
  if (a[kAttrTxInfo]) {
    const int n = nla_len(a[kAttrTxInfo]);
    if (n % kTxRateSize != 0 || static_cast<std::size_t>(n) > kTxRateSize * kMaxTxRates)
      return Unexpected{FrameError::kBadTxInfo};
    const auto* r = static_cast<const std::uint8_t*>(nla_data(a[kAttrTxInfo]));
    f.tx_info.assign(r, r + n);
  }
  if (a[kAttrFreq] && nla_len(a[kAttrFreq]) == 4)
    f.freq_mhz = nla_get_u32(a[kAttrFreq]);
  return f;
}

void put_rx_frame(nl_msg* msg, const MacAddress& receiver, std::span<const std::uint8_t> frame,
                  std::uint32_t rx_rate, std::int32_t signal_dbm,
                  std::optional<std::uint32_t> freq) {
  nla_put(msg, kAttrAddrReceiver, 6, receiver.data());
  nla_put(msg, kAttrFrame, static_cast<int>(frame.size()), frame.data());
  nla_put_u32(msg, kAttrRxRate, rx_rate);
  nla_put_u32(msg, kAttrSignal, static_cast<std::uint32_t>(signal_dbm));
  if (freq)
    nla_put_u32(msg, kAttrFreq, *freq);
}

void put_tx_info(nl_msg* msg, const TxFrame& tx, bool acked, std::int32_t signal_dbm) {
  std::uint32_t flags = tx.flags;
  if (acked)
    flags |= kTxStatAck;
  nla_put(msg, kAttrAddrTransmitter, 6, tx.transmitter.data());
  nla_put_u32(msg, kAttrFlags, flags);
  nla_put_u32(msg, kAttrSignal, static_cast<std::uint32_t>(signal_dbm));
  nla_put(msg, kAttrTxInfo, static_cast<int>(tx.tx_info.size()), tx.tx_info.data());
  nla_put_u64(msg, kAttrCookie, tx.cookie);
}

}  // namespace tb::emu::radio::hwsim
