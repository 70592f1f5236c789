#pragma once
/// @file The road-side unit's signal service (issue 34): MAPEM once a second, SPATEM ten times
/// a second and at once on every state change, from the latest signal feed, over BTP-B with GN
/// single-hop broadcast (README.md, "RsuService").

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <vector>

#include "common/clock/runtime.hpp"
#include "common/wire/sim_protocol.hpp"
#include "its-station/facilities/transport.hpp"
#include "its-station/rsu/mapem_builder.hpp"
#include "its-station/rsu/spatem_builder.hpp"

namespace tb::its::rsu {

/// BTP-B well-known ports of TS 103 301 / TS 103 248.
inline constexpr std::uint16_t kBtpPortMapem = 2003;  // = btp::kPortMapem
inline constexpr std::uint16_t kBtpPortSpatem = 2004;

struct RsuConfig {
  /// TS 103 301 / C-Roads: MAPEM about once a second, SPATEM up to ten times (README.md).
  clock::Duration mapem_interval = std::chrono::seconds{1};
  clock::Duration spatem_interval = std::chrono::milliseconds{100};
  /// A feed older than this sends no SPATEM: the controller's states are no longer known. The
  /// feed repeats at least once a second (sim-server's SignalStates), so 2 s is two misses.
  clock::Duration feed_stale_after = std::chrono::seconds{2};
};

class RsuService {
 public:
  struct Counters {
    std::uint64_t mapem_sent = 0;
    std::uint64_t spatem_sent = 0;
    std::uint64_t spatem_on_change = 0;  ///< of spatem_sent: sent at once on a state change
    std::uint64_t spatem_stale = 0;      ///< SPATEMs not sent because the feed was stale
    std::uint64_t feed_datagrams = 0;    ///< feed datagrams received, malformed ones included
    std::uint64_t feed_malformed = 0;
    std::uint64_t feed_foreign = 0;  ///< well-formed, but without a group of our junction
    std::uint64_t send_errors = 0;   ///< the network layer refused (no position yet, link)
    std::uint64_t encode_errors = 0;
  };
  /// Called for each message handed to the network: its BTP port, whether it was a SPATEM sent
  /// on a change, and its bytes (for traces and the latency measurement).
  using SentListener =
      std::function<void(std::uint16_t port, bool on_change, std::span<const std::uint8_t>)>;

  RsuService(clock::Runtime& runtime, facilities::MessageSender& sender, IntersectionMap map,
             RsuConfig config = {});
  ~RsuService();
  RsuService(const RsuService&) = delete;
  RsuService& operator=(const RsuService&) = delete;

  /// Sends the first MAPEM now and starts both timers.
  void start();
  void stop();

  /// One datagram of the signal feed (signal_feed.hpp): parsed, counted; a malformed one is
  /// logged once (the first) and dropped.
  void on_datagram(std::span<const std::uint8_t> datagram);
  /// Signal states from the feed: kept as the latest; a SPATEM goes out at once when a group of
  /// our junction shows another state than in the last SPATEM sent.
  void on_signal_states(const wire::sim::SignalStates& states);

  const Counters& counters() const { return counters_; }
  /// Milliseconds since the last feed with our junction's groups arrived; none before the first.
  std::optional<std::int64_t> last_feed_age_ms() const;
  const IntersectionMap& map() const { return map_; }
  void set_sent_listener(SentListener l) { sent_listener_ = std::move(l); }

 private:
  void send_mapem();
  void send_spatem(bool on_change);
  void schedule_spatem(clock::SteadyTime when);
  bool stale(clock::SteadyTime now) const;

  clock::Runtime& runtime_;
  facilities::MessageSender& sender_;
  IntersectionMap map_;
  RsuConfig config_;
  SpatemBuilder spatem_;
  Counters counters_;
  SentListener sent_listener_;
  bool running_ = false;
  clock::TimerId mapem_timer_ = 0;
  clock::TimerId spatem_timer_ = 0;
  clock::SteadyTime next_mapem_{};

  std::optional<wire::sim::SignalStates> latest_;  ///< our junction's groups only
  clock::SteadyTime latest_at_{};
  std::vector<wire::sim::SignalGroupState> last_sent_;
  bool stale_said_ = false;
  bool malformed_said_ = false;
  bool send_error_said_ = false;
};

}  // namespace tb::its::rsu
