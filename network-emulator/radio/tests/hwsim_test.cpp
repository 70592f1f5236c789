// The hwsim medium's logic without the kernel: frame messages in and out, and the
// per-receiver decision.

#include <netlink/attr.h>
#include <netlink/genl/genl.h>
#include <netlink/msg.h>

#include <gtest/gtest.h>

#include "network-emulator/radio/hwsim.hpp"
#include "network-emulator/radio/hwsim_radios.hpp"

namespace tb::emu::radio {
namespace {

constexpr int kFakeFamily = 0x20;

NlMsgPtr frame_message(std::uint8_t cmd = hwsim::kCmdFrame) {
  NlMsgPtr m(nlmsg_alloc());
  genlmsg_put(m.get(), 0, 0, kFakeFamily, 0, 0, cmd, hwsim::kVersion);
  return m;
}

// A broadcast data frame as mac80211 hands OCB traffic to hwsim: FC, duration, addr1..3.
std::vector<std::uint8_t> dot11(const MacAddress& addr1) {
  std::vector<std::uint8_t> f(24 + 8, 0xaa);
  f[0] = 0x08;  // type data
  f[1] = f[2] = f[3] = 0x00;
  std::copy(addr1.begin(), addr1.end(), f.begin() + 4);
  return f;
}

TEST(HwsimFrame, ParsesWhatTheKernelSends) {
  auto m = frame_message();
  const MacAddress tx = station_mac(7);
  const auto f = dot11({0xff, 0xff, 0xff, 0xff, 0xff, 0xff});
  const std::uint8_t rates[] = {0, 1, 0xff, 0};
  nla_put(m.get(), hwsim::kAttrAddrTransmitter, 6, tx.data());
  nla_put(m.get(), hwsim::kAttrFrame, static_cast<int>(f.size()), f.data());
  nla_put_u32(m.get(), hwsim::kAttrFlags, hwsim::kTxCtlNoAck);
  nla_put(m.get(), hwsim::kAttrTxInfo, sizeof rates, rates);
  nla_put_u64(m.get(), hwsim::kAttrCookie, 0x1122334455667788ull);
  nla_put_u32(m.get(), hwsim::kAttrFreq, 5900);
  auto parsed = hwsim::parse_frame(m.get());
  ASSERT_TRUE(parsed) << hwsim::to_string(parsed.error());
  EXPECT_EQ(parsed->transmitter, tx);
  EXPECT_EQ(parsed->frame, f);
  EXPECT_EQ(parsed->flags, hwsim::kTxCtlNoAck);
  EXPECT_EQ(parsed->cookie, 0x1122334455667788ull);
  EXPECT_EQ(parsed->tx_info, std::vector<std::uint8_t>(rates, rates + 4));
  EXPECT_EQ(parsed->freq_mhz, 5900u);

  // The TX status echoes cookie, rates and transmitter, and adds the ACK flag when asked.
  auto status = frame_message(hwsim::kCmdTxInfoFrame);
  hwsim::put_tx_info(status.get(), *parsed, true, -60);
  nlattr* a[hwsim::kAttrMax + 1] = {};
  ASSERT_EQ(genlmsg_parse(nlmsg_hdr(status.get()), 0, a, hwsim::kAttrMax, nullptr), 0);
  EXPECT_EQ(nla_get_u64(a[hwsim::kAttrCookie]), 0x1122334455667788ull);
  EXPECT_EQ(nla_get_u32(a[hwsim::kAttrFlags]), hwsim::kTxCtlNoAck | hwsim::kTxStatAck);
  EXPECT_EQ(nla_len(a[hwsim::kAttrTxInfo]), 4);
  EXPECT_EQ(static_cast<std::int32_t>(nla_get_u32(a[hwsim::kAttrSignal])), -60);
}

TEST(HwsimFrame, RejectsMissingOrMisshapenAttributes) {
  const MacAddress tx = station_mac(7);
  const auto f = dot11(station_mac(8));
  struct Case {
    const char* name;
    std::function<void(nl_msg*)> fill;
    hwsim::FrameError expected;
  };
  const std::vector<Case> cases = {
      {"no transmitter",
       [&](nl_msg* m) { nla_put(m, hwsim::kAttrFrame, static_cast<int>(f.size()), f.data()); },
       hwsim::FrameError::kNoTransmitter},
      {"short transmitter",
       [&](nl_msg* m) { nla_put(m, hwsim::kAttrAddrTransmitter, 5, tx.data()); },
       hwsim::FrameError::kNoTransmitter},
      {"one-byte frame",
       [&](nl_msg* m) {
         nla_put(m, hwsim::kAttrAddrTransmitter, 6, tx.data());
         nla_put(m, hwsim::kAttrFrame, 1, f.data());
       },
       hwsim::FrameError::kNoFrame},
      {"no flags",
       [&](nl_msg* m) {
         nla_put(m, hwsim::kAttrAddrTransmitter, 6, tx.data());
         nla_put(m, hwsim::kAttrFrame, static_cast<int>(f.size()), f.data());
         nla_put_u64(m, hwsim::kAttrCookie, 1);
       },
       hwsim::FrameError::kBadFlags},
      {"short cookie",
       [&](nl_msg* m) {
         nla_put(m, hwsim::kAttrAddrTransmitter, 6, tx.data());
         nla_put(m, hwsim::kAttrFrame, static_cast<int>(f.size()), f.data());
         nla_put_u32(m, hwsim::kAttrFlags, 0);
         nla_put_u32(m, hwsim::kAttrCookie, 1);
       },
       hwsim::FrameError::kNoCookie},
      {"five rates",
       [&](nl_msg* m) {
         const std::uint8_t rates[10] = {};
         nla_put(m, hwsim::kAttrAddrTransmitter, 6, tx.data());
         nla_put(m, hwsim::kAttrFrame, static_cast<int>(f.size()), f.data());
         nla_put_u32(m, hwsim::kAttrFlags, 0);
         nla_put_u64(m, hwsim::kAttrCookie, 1);
         nla_put(m, hwsim::kAttrTxInfo, sizeof rates, rates);
       },
       hwsim::FrameError::kBadTxInfo},
  };
  for (const auto& c : cases) {
    auto m = frame_message();
    c.fill(m.get());
    auto parsed = hwsim::parse_frame(m.get());
    ASSERT_FALSE(parsed) << c.name;
    EXPECT_EQ(parsed.error(), c.expected) << c.name << ": " << hwsim::to_string(parsed.error());
  }
  auto other = frame_message(hwsim::kCmdTxInfoFrame);
  EXPECT_EQ(hwsim::parse_frame(other.get()).error(), hwsim::FrameError::kNotAFrame);
}

TEST(HwsimFrame, RxFrameCarriesReceiverSignalAndFrequency) {
  auto m = frame_message();
  const auto f = dot11(station_mac(9));
  hwsim::put_rx_frame(m.get(), station_mac(9), f, 0, -77, 5900u);
  nlattr* a[hwsim::kAttrMax + 1] = {};
  ASSERT_EQ(genlmsg_parse(nlmsg_hdr(m.get()), 0, a, hwsim::kAttrMax, nullptr), 0);
  ASSERT_EQ(nla_len(a[hwsim::kAttrAddrReceiver]), 6);
  EXPECT_EQ(std::memcmp(nla_data(a[hwsim::kAttrAddrReceiver]), station_mac(9).data(), 6), 0);
  EXPECT_EQ(nla_len(a[hwsim::kAttrFrame]), static_cast<int>(f.size()));
  EXPECT_EQ(static_cast<std::int32_t>(nla_get_u32(a[hwsim::kAttrSignal])), -77);
  EXPECT_EQ(nla_get_u32(a[hwsim::kAttrFreq]), 5900u);
}

class HwsimRouterTest : public ::testing::Test {
 protected:
  void SetUp() override {
    positions.set(1, {{0, 0, 0}, 0});
    positions.set(2, {{100, 0, 0}, 0});
    positions.set(3, {{5000, 0, 0}, 0});
    for (StationId id : {1u, 2u, 3u})
      radios.push_back({id, "r" + std::to_string(id), station_mac(id), "ns"});
  }
  PositionTable positions;
  std::vector<HwsimRadio> radios;
  const MacAddress monitor{0x06, 0, 0, 0, 0, 1};
  const MacAddress broadcast{0xff, 0xff, 0xff, 0xff, 0xff, 0xff};
};

TEST_F(HwsimRouterTest, DecidesPerReceiverWithPathLossSignalAndFeedsTheMonitor) {
  scenario::ChannelModel m;
  m.kind = scenario::ChannelModel::Kind::kLogDistance;
  Channel ch(m, positions, 1);
  HwsimRouter router(ch, radios, monitor);
  const auto plan = router.plan(station_mac(1), dot11(broadcast));
  ASSERT_EQ(plan.sender, 1u);
  // 2 at 100 m hears it; 3 at 5 km does not; the monitor hears everything.
  ASSERT_EQ(plan.deliveries.size(), 2u);
  EXPECT_EQ(plan.deliveries[0].receiver, station_mac(2));
  // 23 dBm − (47.86 + 20 log10(100)) = −64.86 dBm.
  EXPECT_EQ(plan.deliveries[0].signal_dbm, -65);
  EXPECT_EQ(plan.deliveries[1].receiver, monitor);
  EXPECT_TRUE(plan.acked);  // group frames are never acknowledged, so report them done
  EXPECT_EQ(ch.links().at({1, 3}).dropped[static_cast<int>(DropReason::kBelowSensitivity)], 1u);
}

TEST_F(HwsimRouterTest, UnicastIsAckedOnlyWhenTheAddresseeReceivedIt) {
  scenario::ChannelModel m;
  m.kind = scenario::ChannelModel::Kind::kRange;
  m.range_m = 300;
  Channel ch(m, positions, 1);
  HwsimRouter router(ch, radios, std::nullopt);
  EXPECT_TRUE(router.plan(station_mac(1), dot11(station_mac(2))).acked);
  EXPECT_FALSE(router.plan(station_mac(1), dot11(station_mac(3))).acked);
  const auto nominal = router.plan(station_mac(1), dot11(station_mac(2)));
  ASSERT_EQ(nominal.deliveries.size(), 1u);
  EXPECT_EQ(nominal.deliveries[0].signal_dbm, HwsimRouter::kNominalSignalDbm);
}

TEST_F(HwsimRouterTest, FramesFromRadiosNotOursGoNowhere) {
  scenario::ChannelModel m;
  Channel ch(m, positions, 1);
  HwsimRouter router(ch, radios, monitor);
  const auto plan = router.plan(station_mac(42), dot11(broadcast));
  EXPECT_FALSE(plan.sender);
  EXPECT_TRUE(plan.deliveries.empty());
  EXPECT_TRUE(ch.links().empty());
}

}  // namespace
}  // namespace tb::emu::radio
