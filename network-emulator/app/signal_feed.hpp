#pragma once
/// @file SignalFeed: the traffic lights' states from the sim-clients to the road-side units
/// (issue 34; docs/wire.md, "Signal feed"). Each datagram in is one SignalStates of every
/// junction; each RSU gets at once the groups of its own junction, one datagram each. A real RSU
/// hears them from its traffic controller; here the emulator stands in for that link as it
/// does for the GNSS receiver and the CAN bus. No sockets: the sinks are injected.

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "common/trace/tracer.hpp"
#include "common/wire/signal_feed.hpp"
#include "network-emulator/app/datagram_sink.hpp"

namespace tb::emu {

struct SignalFeedCounters {
  std::uint64_t datagrams = 0;  ///< received
  std::uint64_t malformed = 0;  ///< did not decode (wire::decode_signal_feed)
  std::array<std::uint64_t, wire::kSignalFeedErrorCount> malformed_by_error{};
  /// Not newer than the last one taken (by world_time_ms): another client's copy of a message
  /// already passed on, or an older one overtaken.
  std::uint64_t duplicates = 0;
  std::uint64_t taken = 0;      ///< passed on to the RSUs
  std::uint64_t sent = 0;       ///< datagrams to RSUs
  std::uint64_t failed = 0;     ///< datagrams to RSUs the socket refused
  std::uint64_t no_groups = 0;  ///< messages without any group of an RSU's junction (per RSU)
};

/// How far world_time_ms may jump back before the feed takes it for a new world (a restarted
/// sim-server) rather than a late copy: ten seconds is far beyond any client's lag.
inline constexpr std::int64_t kSignalFeedRestartMs = 10'000;

class SignalFeed {
 public:
  struct Rsu {
    std::uint32_t station_id = 0;
    std::uint16_t intersection_id = 0;  ///< its junction's IntersectionID
    DatagramSink* sink = nullptr;       ///< null: counted as failed
  };
  SignalFeed(std::vector<Rsu> rsus, trace::Tracer& tracer);

  /// Handles one datagram from a sim-client. Returns whether it was passed on.
  bool handle_datagram(std::span<const std::uint8_t> bytes);
  const SignalFeedCounters& counters() const { return counters_; }
  std::size_t rsus() const { return rsus_.size(); }

 private:
  std::vector<Rsu> rsus_;
  trace::Tracer& tracer_;
  SignalFeedCounters counters_;
  std::optional<std::int64_t> last_world_ms_;
  std::array<bool, wire::kSignalFeedErrorCount> logged_{};
  wire::sim::SignalStates own_;  ///< one RSU's part; capacity reused
};

}  // namespace tb::emu
