#include "network-emulator/radio/hwsim_radios.hpp"

#include <linux/nl80211.h>
#include <net/if.h>
#include <netlink/attr.h>
#include <netlink/genl/genl.h>
#include <netlink/msg.h>
#include <netlink/netlink.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include <spdlog/spdlog.h>

#include "network-emulator/radio/netns.hpp"

namespace tb::emu::radio {

std::string_view to_string(MediumKind k) {
  return k == MediumKind::kHwsim ? "mac80211_hwsim radios" : "the veth stand-in medium";
}

MediumChoice choose_medium(std::string_view mode) {
  if (mode == "veth")
    return {MediumKind::kVeth, "chosen with --mode veth"};
  const bool loaded = std::filesystem::exists("/sys/module/mac80211_hwsim");
  std::optional<int> family;
  if (loaded) {
    GenlSocket genl;
    family = genl.family(hwsim::kFamily);
  }
  if (family)
    return {MediumKind::kHwsim,
            "the kernel has mac80211_hwsim: generic-netlink family MAC80211_HWSIM answers"};
  const std::string missing =
      loaded ? "mac80211_hwsim is loaded but its generic-netlink family MAC80211_HWSIM does not "
               "answer"
             : "the kernel has no mac80211_hwsim loaded (`modprobe mac80211_hwsim radios=0` "
               "loads it without radios of its own)";
  if (mode == "hwsim")
    throw std::runtime_error("--mode hwsim: " + missing + "; or use --mode veth");
  return {MediumKind::kVeth, missing};
}

namespace {

[[noreturn]] void fail(const std::string& what, const GenlAnswer& a) {
  throw std::runtime_error(what + ": " + a.describe());
}

int resolve(GenlSocket& genl, const char* name, const std::string& hint) {
  const auto id = genl.family(name);
  if (!id)
    throw std::runtime_error(std::string("generic-netlink family ") + name + " not found; " + hint);
  return *id;
}

// Sets a wiphy's or an interface's channel to the control channel, 10 MHz wide.
void put_cch(nl_msg* m) {
  nla_put_u32(m, NL80211_ATTR_WIPHY_FREQ, kCchFrequencyMhz);
  nla_put_u32(m, NL80211_ATTR_CHANNEL_WIDTH, NL80211_CHAN_WIDTH_10);
  nla_put_u32(m, NL80211_ATTR_CENTER_FREQ1, kCchFrequencyMhz);
}

// NL80211_CMD_NEW_INTERFACE; returns the new interface's index.
int new_interface(GenlSocket& genl, int nl80211, std::uint32_t wiphy, const std::string& ifname,
                  nl80211_iftype type, const std::string& who) {
  auto m = genl.message(nl80211, NL80211_CMD_NEW_INTERFACE, 0);
  nla_put_u32(m.get(), NL80211_ATTR_WIPHY, wiphy);
  nla_put_string(m.get(), NL80211_ATTR_IFNAME, ifname.c_str());
  nla_put_u32(m.get(), NL80211_ATTR_IFTYPE, type);
  int ifindex = 0;
  const GenlAnswer a = genl.request(std::move(m), [&](nl_msg* reply) {
    nlattr* tb[NL80211_ATTR_MAX + 1] = {};
    if (genlmsg_parse(nlmsg_hdr(reply), 0, tb, NL80211_ATTR_MAX, nullptr) == 0 &&
        tb[NL80211_ATTR_IFINDEX] && nla_len(tb[NL80211_ATTR_IFINDEX]) == 4)
      ifindex = static_cast<int>(nla_get_u32(tb[NL80211_ATTR_IFINDEX]));
  });
  if (!a.ok())
    fail(who + ": cannot create " + ifname, a);
  if (ifindex == 0)
    ifindex = static_cast<int>(if_nametoindex(ifname.c_str()));
  return ifindex;
}

std::string join_advice() {
  return "5.9 GHz is disabled under most regulatory domains. radio-medium makes its radios "
         "with hwsim's custom regulatory domain (HWSIM_ATTR_REG_CUSTOM_REG = 0, \"99\", which "
         "includes the ITS band); if the kernel still refuses, reload the module with it for "
         "every radio: `modprobe -r mac80211_hwsim && modprobe mac80211_hwsim radios=0 "
         "regtest=5`, or set a regulatory domain that allows 5850-5925 MHz";
}

}  // namespace

HwsimRadios::HwsimRadios(const std::vector<StationSpec>& stations, const std::string& prefix)
    : prefix_(prefix) {
  hwsim_family_ = resolve(genl_, hwsim::kFamily, "load it with `modprobe mac80211_hwsim radios=0`");
  nl80211_family_ = resolve(genl_, NL80211_GENL_NAME, "the kernel has no cfg80211");
  try {
    // Every radio is made here before any moves: a radio hears only radios of the netgroup of
    // the namespace that created it.
    for (const StationSpec& s : stations) {
      HwsimRadio r{s.id, prefix_ + std::to_string(s.id), station_mac(s.id), s.netns};
      create_radio(r.name, r.address);
      radios_.push_back(r);
    }
    create_radio(monitor_ifname(), monitor_address_);

    for (const HwsimRadio& r : radios_) {
      const NetnsFd ns = NetnsFd::open(r.netns);
      auto m = genl_.message(nl80211_family_, NL80211_CMD_SET_WIPHY_NETNS, 0);
      nla_put_u32(m.get(), NL80211_ATTR_WIPHY, wiphy_index(r.name));
      nla_put_u32(m.get(), NL80211_ATTR_NETNS_FD, static_cast<std::uint32_t>(ns.fd()));
      if (auto a = genl_.request(std::move(m)); !a.ok())
        fail("station " + std::to_string(r.station) + ": cannot move radio " + r.name + " into " +
                 ns.path(),
             a);
      // In the station's namespace: wlan0 in OCB mode, up, on the control channel.
      in_netns(ns, [&] {
        GenlSocket genl;
        const int nl80211 = resolve(genl, NL80211_GENL_NAME, "no cfg80211 in " + ns.path());
        std::uint32_t wiphy = 0;
        {
          // The index is global, but look it up here to be sure the move happened.
          auto dump = genl.message(nl80211, NL80211_CMD_GET_WIPHY, 0, true);
          nla_put_flag(dump.get(), NL80211_ATTR_SPLIT_WIPHY_DUMP);
          bool found = false;
          genl.request(std::move(dump), [&](nl_msg* reply) {
            nlattr* tb[NL80211_ATTR_MAX + 1] = {};
            if (genlmsg_parse(nlmsg_hdr(reply), 0, tb, NL80211_ATTR_MAX, nullptr) < 0 ||
                !tb[NL80211_ATTR_WIPHY_NAME] || !tb[NL80211_ATTR_WIPHY])
              return;
            if (r.name == nla_get_string(tb[NL80211_ATTR_WIPHY_NAME])) {
              wiphy = nla_get_u32(tb[NL80211_ATTR_WIPHY]);
              found = true;
            }
          });
          if (!found)
            throw std::runtime_error("station " + std::to_string(r.station) + ": radio " + r.name +
                                     " did not arrive in " + ns.path());
        }
        const std::string who = "station " + std::to_string(r.station) + " (" + ns.path() + ")";
        const int ifindex =
            new_interface(genl, nl80211, wiphy, kStationIfname, NL80211_IFTYPE_OCB, who);
        RouteSocket rtnl;
        rtnl.set_up(kStationIfname);
        auto join = genl.message(nl80211, NL80211_CMD_JOIN_OCB, 0);
        nla_put_u32(join.get(), NL80211_ATTR_IFINDEX, static_cast<std::uint32_t>(ifindex));
        put_cch(join.get());
        if (auto a = genl.request(std::move(join)); !a.ok())
          throw std::runtime_error(who + ": cannot join " + std::to_string(kCchFrequencyMhz) +
                                   " MHz / 10 MHz in OCB mode on " + kStationIfname + ": " +
                                   a.describe() + ". " + join_advice());
      });
      spdlog::debug("radio: station {}: radio {} ({}) in {}, {} in OCB mode on {} MHz", r.station,
                    r.name, to_string(r.address), r.netns, kStationIfname, kCchFrequencyMhz);
    }

    // The host's monitor interface, for captures of everything on the air.
    const int mon = new_interface(genl_, nl80211_family_, wiphy_index(monitor_ifname()),
                                  monitor_ifname(), NL80211_IFTYPE_MONITOR, "monitor radio");
    RouteSocket rtnl;
    rtnl.set_up(monitor_ifname());
    auto ch = genl_.message(nl80211_family_, NL80211_CMD_SET_WIPHY, 0);
    nla_put_u32(ch.get(), NL80211_ATTR_IFINDEX, static_cast<std::uint32_t>(mon));
    put_cch(ch.get());
    if (auto a = genl_.request(std::move(ch)); !a.ok())
      throw std::runtime_error("monitor radio: cannot tune " + monitor_ifname() + " to " +
                               std::to_string(kCchFrequencyMhz) + " MHz / 10 MHz: " + a.describe() +
                               ". " + join_advice());
  } catch (...) {
    remove_all();
    throw;
  }
}

HwsimRadios::~HwsimRadios() {
  remove_all();
}

void HwsimRadios::create_radio(const std::string& name, const MacAddress& addr) {
  auto m = genl_.message(hwsim_family_, hwsim::kCmdNewRadio, hwsim::kVersion);
  nla_put_string(m.get(), hwsim::kAttrRadioName, name.c_str());
  nla_put_u32(m.get(), hwsim::kAttrChannels, 1);
  nla_put_flag(m.get(), hwsim::kAttrNoVif);  // wlan0 is made in the station's namespace
  nla_put(m.get(), hwsim::kAttrPermAddr, 6, addr.data());
  nla_put_u32(m.get(), hwsim::kAttrRegCustomReg, 0);
  nla_put_flag(m.get(), hwsim::kAttrDestroyRadioOnClose);
  const GenlAnswer a = genl_.request(std::move(m));
  if (!a.ok())
    fail("cannot create hwsim radio " + name + " (" + to_string(addr) + ")", a);
  created_.push_back(name);  // a.error is the radio's id
}

std::uint32_t HwsimRadios::wiphy_index(const std::string& name) {
  auto dump = genl_.message(nl80211_family_, NL80211_CMD_GET_WIPHY, 0, true);
  nla_put_flag(dump.get(), NL80211_ATTR_SPLIT_WIPHY_DUMP);
  std::optional<std::uint32_t> index;
  const GenlAnswer a = genl_.request(std::move(dump), [&](nl_msg* reply) {
    nlattr* tb[NL80211_ATTR_MAX + 1] = {};
    if (genlmsg_parse(nlmsg_hdr(reply), 0, tb, NL80211_ATTR_MAX, nullptr) < 0 ||
        !tb[NL80211_ATTR_WIPHY_NAME] || !tb[NL80211_ATTR_WIPHY])
      return;
    if (name == nla_get_string(tb[NL80211_ATTR_WIPHY_NAME]))
      index = nla_get_u32(tb[NL80211_ATTR_WIPHY]);
  });
  if (!a.ok() || !index)
    throw std::runtime_error("no wiphy named " + name + " after creating it: " + a.describe());
  return *index;
}

void HwsimRadios::remove_all() noexcept {
  // A radio can be deleted only from the namespace it is in now: the station's, or ours if the
  // station's namespace went away first (cfg80211 then returns the wiphy to the initial one).
  for (const std::string& name : created_) {
    auto del = [&](GenlSocket& g, int family) {
      auto m = g.message(family, hwsim::kCmdDelRadio, hwsim::kVersion);
      nla_put_string(m.get(), hwsim::kAttrRadioName, name.c_str());
      return g.request(std::move(m));
    };
    try {
      bool done = del(genl_, hwsim_family_).ok();
      for (const HwsimRadio& r : radios_) {
        if (done || r.name != name)
          continue;
        const NetnsFd ns = NetnsFd::open(r.netns);
        done = in_netns(ns, [&] {
          GenlSocket g;
          const auto family = g.family(hwsim::kFamily);
          return family && del(g, *family).ok();
        });
      }
      if (!done)
        spdlog::warn(
            "radio: radio {} was not found to delete; the kernel removes it when this "
            "process exits",
            name);
    } catch (const std::exception& e) {
      spdlog::warn("radio: deleting radio {}: {}", name, e.what());
    }
  }
  created_.clear();
}

std::vector<std::string> HwsimRadios::remove_leftovers(const std::string& prefix) {
  GenlSocket genl;
  std::vector<std::string> removed;
  const auto family = genl.family(hwsim::kFamily);
  if (!family)
    return removed;
  std::vector<std::string> names;
  auto dump = genl.message(*family, hwsim::kCmdGetRadio, hwsim::kVersion, true);
  genl.request(std::move(dump), [&](nl_msg* reply) {
    nlattr* tb[hwsim::kAttrMax + 1] = {};
    if (genlmsg_parse(nlmsg_hdr(reply), 0, tb, hwsim::kAttrMax, nullptr) < 0 ||
        !tb[hwsim::kAttrRadioName])
      return;
    const auto* text = static_cast<const char*>(nla_data(tb[hwsim::kAttrRadioName]));
    std::string name(text,
                     strnlen(text, static_cast<std::size_t>(nla_len(tb[hwsim::kAttrRadioName]))));
    if (name.starts_with(prefix))
      names.push_back(std::move(name));
  });
  for (const std::string& name : names) {
    auto m = genl.message(*family, hwsim::kCmdDelRadio, hwsim::kVersion);
    nla_put_string(m.get(), hwsim::kAttrRadioName, name.c_str());
    if (genl.request(std::move(m)).ok())
      removed.push_back(name);
  }
  return removed;
}

// ---------------------------------------------------------------------------------------------

HwsimRouter::HwsimRouter(Channel& channel, const std::vector<HwsimRadio>& radios,
                         std::optional<MacAddress> monitor)
    : channel_(channel), monitor_(monitor) {
  for (const HwsimRadio& r : radios) {
    by_address_[r.address] = r.station;
    by_station_[r.station] = r.address;
  }
}

HwsimRouter::Plan HwsimRouter::plan(const MacAddress& transmitter,
                                    std::span<const std::uint8_t> frame) {
  Plan p;
  auto it = by_address_.find(transmitter);
  if (it == by_address_.end())
    return p;
  p.sender = it->second;
  // IEEE 802.11-2020, 9.3: addr1 (receiver) follows frame control and duration.
  std::optional<MacAddress> addr1;
  if (frame.size() >= 10) {
    addr1.emplace();
    std::memcpy(addr1->data(), frame.data() + 4, 6);
  }
  const bool group = addr1 && ((*addr1)[0] & 0x01);
  p.acked = group;
  for (const auto& [station, address] : by_station_) {
    if (station == *p.sender)
      continue;
    const Decision d = channel_.decide(*p.sender, station);
    if (!d.deliver)
      continue;
    const std::int32_t signal = d.rx_power_dbm
                                    ? static_cast<std::int32_t>(std::lround(*d.rx_power_dbm))
                                    : kNominalSignalDbm;
    p.deliveries.push_back({address, signal, d.delay});
    if (addr1 && *addr1 == address)
      p.acked = true;
  }
  // The monitor hears everything, as a capture on a wired tap would.
  if (monitor_)
    p.deliveries.push_back({*monitor_, kNominalSignalDbm, clock::Duration{0}});
  return p;
}

// ---------------------------------------------------------------------------------------------

HwsimMedium::HwsimMedium(boost::asio::io_context& io, clock::Runtime& runtime, Channel& channel,
                         const HwsimRadios& radios)
    : runtime_(runtime),
      router_(channel, radios.radios(), radios.monitor_address()),
      descriptor_(io) {
  family_ = resolve(genl_, hwsim::kFamily, "load it with `modprobe mac80211_hwsim radios=0`");
}

HwsimMedium::~HwsimMedium() {
  for (clock::TimerId id : timers_)
    runtime_.cancel(id);
}

void HwsimMedium::start() {
  auto reg = genl_.message(family_, hwsim::kCmdRegister, hwsim::kVersion);
  if (auto a = genl_.request(std::move(reg)); !a.ok())
    fail(
        "cannot register as mac80211_hwsim's medium (is wmediumd or another radio-medium "
        "running in this namespace?)",
        a);
  // From here on the socket carries unsolicited frames, not answers to our requests.
  nl_socket_disable_seq_check(genl_.get());
  nl_socket_set_nonblocking(genl_.get());
  nl_socket_set_buffer_size(genl_.get(), 8 << 20, 8 << 20);
  nl_socket_modify_cb(
      genl_.get(), NL_CB_VALID, NL_CB_CUSTOM,
      [](nl_msg* msg, void* self) {
        static_cast<HwsimMedium*>(self)->on_message(msg);
        return static_cast<int>(NL_OK);
      },
      this);
  descriptor_.assign(::dup(nl_socket_get_fd(genl_.get())));
  wait();
}

void HwsimMedium::wait() {
  descriptor_.async_wait(boost::asio::posix::stream_descriptor::wait_read,
                         [this](const boost::system::error_code& ec) {
                           if (ec)
                             return;
                           // Reads what is queued; -NLE_AGAIN just means drained.
                           nl_recvmsgs_default(genl_.get());
                           wait();
                         });
}

void HwsimMedium::on_message(nl_msg* msg) {
  auto tx = hwsim::parse_frame(msg);
  if (!tx) {
    if (tx.error() != hwsim::FrameError::kNotAFrame && bad_messages_++ == 0)
      spdlog::warn("radio: bad message from mac80211_hwsim: {} (counted, said once)",
                   hwsim::to_string(tx.error()));
    return;
  }
  ++frames_in_;
  const HwsimRouter::Plan plan = router_.plan(tx->transmitter, tx->frame);
  if (frame_observer_ && plan.sender)
    frame_observer_(*plan.sender, tx->frame, 0);
  auto frame = std::make_shared<const std::vector<std::uint8_t>>(tx->frame);
  const clock::SteadyTime now = runtime_.steady_now();
  for (const auto& d : plan.deliveries) {
    // As in Medium: a receiver gets frames in the order they were sent, whatever the jitter.
    clock::SteadyTime& last_due = last_due_[d.receiver];
    if (d.delay == clock::Duration{0} && last_due <= now) {
      send_frame(d.receiver, *frame, d.signal_dbm, tx->freq_mhz);
      continue;
    }
    last_due = std::max(now + d.delay, last_due);
    auto id = std::make_shared<clock::TimerId>(0);
    *id = runtime_.schedule_at(last_due, [this, d, frame, freq = tx->freq_mhz, id] {
      timers_.erase(*id);
      send_frame(d.receiver, *frame, d.signal_dbm, freq);
    });
    timers_.insert(*id);
  }
  // The sender learns at once how its frame went: mac80211 holds the skb until then.
  if (plan.sender) {
    auto m = genl_.message(family_, hwsim::kCmdTxInfoFrame, hwsim::kVersion);
    hwsim::put_tx_info(m.get(), *tx, plan.acked, HwsimRouter::kNominalSignalDbm);
    nl_send_auto(genl_.get(), m.get());
  }
}

void HwsimMedium::send_frame(const MacAddress& receiver, const std::vector<std::uint8_t>& frame,
                             std::int32_t signal_dbm, std::optional<std::uint32_t> freq) {
  auto m = genl_.message(family_, hwsim::kCmdFrame, hwsim::kVersion);
  // Rate index 0 is the lowest of the band: 3 Mbit/s on a 10 MHz channel (EN 302 663).
  hwsim::put_rx_frame(m.get(), receiver, frame, 0, signal_dbm, freq);
  nl_send_auto(genl_.get(), m.get());
}

}  // namespace tb::emu::radio
