#pragma once
/// @file Real 802.11p radios: mac80211_hwsim radios made over generic netlink, one per station
/// (moved into its namespace, wlan0 in OCB mode on 5900 MHz / 10 MHz) plus a monitor radio in
/// the emulator's namespace; and the medium between them, registered with hwsim as its frame
/// handler the way wmediumd is, so that the channel model decides every delivery.

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>

#include "common/clock/runtime.hpp"
#include "network-emulator/radio/channel.hpp"
#include "network-emulator/radio/genl.hpp"
#include "network-emulator/radio/hwsim.hpp"
#include "network-emulator/radio/medium.hpp"
#include "network-emulator/radio/veth_radios.hpp"

namespace tb::emu::radio {

enum class MediumKind { kHwsim, kVeth };
std::string_view to_string(MediumKind k);

struct MediumChoice {
  MediumKind kind = MediumKind::kVeth;
  std::string why;  ///< for the one log line that says which radio is in use
};

/// Picks the radio for @p mode ("auto", "hwsim", "veth"). auto takes hwsim when the module is
/// loaded and its generic-netlink family answers; it never loads the module itself (a bare
/// `modprobe mac80211_hwsim` would add two radios of its own). @throws std::runtime_error
/// when hwsim is asked for and missing, saying how to load it.
MediumChoice choose_medium(std::string_view mode);

/// ITS-G5 control channel (EN 302 663, clause 4.2: G5-CCH, channel 180): 5900 MHz, 10 MHz wide.
inline constexpr std::uint32_t kCchFrequencyMhz = 5900;

struct HwsimRadio {
  StationId station = 0;
  std::string name;  ///< wiphy name, PREFIX + station id
  MacAddress address{};
  std::string netns;
};

class HwsimRadios {
 public:
  /// Creates a radio per station and the monitor radio PREFIX + "mon"; each radio is made with
  /// HWSIM_ATTR_DESTROY_RADIO_ON_CLOSE, so the kernel removes them even if this process is
  /// killed. @throws std::runtime_error naming the station and what to do.
  HwsimRadios(const std::vector<StationSpec>& stations, const std::string& prefix);
  ~HwsimRadios();
  HwsimRadios(const HwsimRadios&) = delete;
  HwsimRadios& operator=(const HwsimRadios&) = delete;

  const std::vector<HwsimRadio>& radios() const { return radios_; }
  const MacAddress& monitor_address() const { return monitor_address_; }
  std::string monitor_ifname() const { return prefix_ + "mon"; }

  /// Deletes radios named PREFIX* in this namespace (left by a run from before radios were
  /// destroyed on close). Returns their names.
  static std::vector<std::string> remove_leftovers(const std::string& prefix);

 private:
  void create_radio(const std::string& name, const MacAddress& addr);
  std::uint32_t wiphy_index(const std::string& name);
  void remove_all() noexcept;

  std::string prefix_;
  GenlSocket genl_;  // owns the radios (destroy on close): lives as long as they should
  int hwsim_family_ = 0;
  int nl80211_family_ = 0;
  std::vector<HwsimRadio> radios_;
  std::vector<std::string> created_;
  MacAddress monitor_address_{0x06, 0x00, 0x00, 0x00, 0x00, 0x01};
};

/// The per-receiver decision for one transmitted frame: pure, so that it is tested without
/// the kernel.
class HwsimRouter {
 public:
  struct Delivery {
    MacAddress receiver{};
    std::int32_t signal_dbm = 0;
    clock::Duration delay{};
  };
  struct Plan {
    std::optional<StationId> sender;  ///< empty: not one of our radios, nothing is delivered
    std::vector<Delivery> deliveries;
    bool acked = false;  ///< group frames, or the addressed station received it
  };

  /// Signal reported for models without a path loss (ideal, range).
  static constexpr std::int32_t kNominalSignalDbm = -50;

  HwsimRouter(Channel& channel, const std::vector<HwsimRadio>& radios,
              std::optional<MacAddress> monitor);
  /// @p frame is the 802.11 frame (its addr1 decides whether an ACK is reported).
  Plan plan(const MacAddress& transmitter, std::span<const std::uint8_t> frame);

 private:
  Channel& channel_;
  std::map<MacAddress, StationId> by_address_;
  std::map<StationId, MacAddress> by_station_;
  std::optional<MacAddress> monitor_;
};

/// Registers with hwsim (HWSIM_CMD_REGISTER) and from then on carries every frame of the
/// radios of this namespace's netgroup: HWSIM_CMD_FRAME in, HWSIM_CMD_FRAME out to each
/// receiver the channel lets it reach (after the model's delay), HWSIM_CMD_TX_INFO_FRAME back
/// to the sender.
class HwsimMedium {
 public:
  HwsimMedium(boost::asio::io_context& io, clock::Runtime& runtime, Channel& channel,
              const HwsimRadios& radios);
  ~HwsimMedium();
  /// @throws std::runtime_error if hwsim refuses the registration (another medium holds it).
  void start();

  std::uint64_t frames_in() const { return frames_in_; }
  std::uint64_t bad_messages() const { return bad_messages_; }
  /// Called with every frame of one of our radios (802.11), before the channel decides.
  void set_frame_observer(FrameObserver o) { frame_observer_ = std::move(o); }

 private:
  void wait();
  void on_message(nl_msg* msg);
  void send_frame(const MacAddress& receiver, const std::vector<std::uint8_t>& frame,
                  std::int32_t signal_dbm, std::optional<std::uint32_t> freq);

  clock::Runtime& runtime_;
  HwsimRouter router_;
  GenlSocket genl_;
  int family_ = 0;
  boost::asio::posix::stream_descriptor descriptor_;
  std::set<clock::TimerId> timers_;
  std::map<MacAddress, clock::SteadyTime> last_due_;
  FrameObserver frame_observer_;
  std::uint64_t frames_in_ = 0;
  std::uint64_t bad_messages_ = 0;
};

}  // namespace tb::emu::radio
