#pragma once
/// @file mac80211_hwsim's generic-netlink interface (family "MAC80211_HWSIM"). The kernel keeps
/// these numbers in drivers/net/wireless/virtual/mac80211_hwsim.h, which is not exported to
/// user space; they are part of its ABI and never renumbered.

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "common/util/expected.hpp"
#include "network-emulator/radio/rtnl.hpp"

struct nl_msg;

namespace tb::emu::radio::hwsim {

inline constexpr const char* kFamily = "MAC80211_HWSIM";
inline constexpr int kVersion = 1;

enum Command : std::uint8_t {
  kCmdRegister = 1,
  kCmdFrame = 2,
  kCmdTxInfoFrame = 3,
  kCmdNewRadio = 4,
  kCmdDelRadio = 5,
  kCmdGetRadio = 6,
};

enum Attr : int {
  kAttrAddrReceiver = 1,
  kAttrAddrTransmitter = 2,
  kAttrFrame = 3,
  kAttrFlags = 4,
  kAttrRxRate = 5,
  kAttrSignal = 6,
  kAttrTxInfo = 7,
  kAttrCookie = 8,
  kAttrChannels = 9,
  kAttrRadioId = 10,
  kAttrRegHintAlpha2 = 11,
  kAttrRegCustomReg = 12,
  kAttrRegStrictReg = 13,
  kAttrSupportP2pDevice = 14,
  kAttrUseChanctx = 15,
  kAttrDestroyRadioOnClose = 16,
  kAttrRadioName = 17,
  kAttrNoVif = 18,
  kAttrFreq = 19,
  kAttrPad = 20,
  kAttrTxInfoFlags = 21,
  kAttrPermAddr = 22,
  kAttrMax = 22,  ///< the highest attribute this code reads
};

enum TxFlags : std::uint32_t {
  kTxCtlReqTxStatus = 1u << 0,
  kTxCtlNoAck = 1u << 1,
  kTxStatAck = 1u << 2,
};

/// One struct hwsim_tx_rate {s8 idx; u8 count;} per retry stage; IEEE80211_TX_MAX_RATES = 4.
inline constexpr std::size_t kTxRateSize = 2;
inline constexpr std::size_t kMaxTxRates = 4;

/// A frame a radio transmitted, as hwsim hands it to the registered medium (HWSIM_CMD_FRAME).
struct TxFrame {
  MacAddress transmitter{};         ///< the radio's address: its PERM_ADDR when given one
  std::vector<std::uint8_t> frame;  ///< the 802.11 frame
  std::uint32_t flags = 0;
  std::uint64_t cookie = 0;
  std::vector<std::uint8_t> tx_info;  ///< hwsim_tx_rate array, returned in the TX status
  std::optional<std::uint32_t> freq_mhz;
};

enum class FrameError {
  kNotAFrame,      ///< another command
  kMalformed,      ///< attributes do not parse
  kNoTransmitter,  ///< ADDR_TRANSMITTER missing or not 6 bytes
  kNoFrame,        ///< FRAME missing or shorter than an 802.11 header's frame control
  kNoCookie,       ///< COOKIE missing or not 8 bytes
  kBadTxInfo,      ///< TX_INFO longer than kMaxTxRates entries or not whole entries
  kBadFlags,       ///< FLAGS missing or not 4 bytes
};
std::string_view to_string(FrameError e);

/// Reads a HWSIM_CMD_FRAME message; every attribute is length-checked before use.
Expected<TxFrame, FrameError> parse_frame(nl_msg* msg);

/// Builds the message that puts @p frame into the radio @p receiver (HWSIM_CMD_FRAME).
void put_rx_frame(nl_msg* msg, const MacAddress& receiver, std::span<const std::uint8_t> frame,
                  std::uint32_t rx_rate, std::int32_t signal_dbm,
                  std::optional<std::uint32_t> freq);
/// Builds the TX status for @p tx (HWSIM_CMD_TX_INFO_FRAME); @p acked sets HWSIM_TX_STAT_ACK.
void put_tx_info(nl_msg* msg, const TxFrame& tx, bool acked, std::int32_t signal_dbm);

}  // namespace tb::emu::radio::hwsim
