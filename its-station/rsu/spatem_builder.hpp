#pragma once
/// @file The SPATEM of one intersection (ETSI TS 103 301, ISO TS 19091 SPAT) from the signal
/// states the traffic controller feeds the road-side unit (common/wire SignalStates, world-clock
/// UTC ms) and the station's ITS clock.

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "common/util/expected.hpp"
#include "common/wire/sim_protocol.hpp"
#include "its-station/messages/spatem.hpp"

namespace tb::its::rsu {

/// The TimeMark (ISO TS 19091 / SAE J2735 DE_TimeMark) of UTC @p at_ms seen at UTC @p now_ms:
/// tenths of a second into the current or next hour. An instant an hour or more ahead is 36000
/// ("time > 3600 s" in the module's comment), an unknown one (@p at_ms 0, the feed's "no
/// change planned") 36001. The world clock counts no leap seconds (Unix ms), so 35991..35999 are
/// never used for one.
messages::TimeMark time_mark(std::int64_t at_ms, std::int64_t now_ms);

/// Whether @p a and @p b show the same state for every group (the times may differ): a
/// difference is what makes the RSU send a SPATEM at once.
bool same_states(const wire::sim::SignalStates& a, const wire::sim::SignalStates& b);

/// Builds SPATEMs of intersection @p intersection_id; keeps one message (~0.5 MB) and one
/// encoding buffer for its lifetime, so building allocates nothing after the first.
class SpatemBuilder {
 public:
  explicit SpatemBuilder(std::uint16_t intersection_id);
  ~SpatemBuilder();
  SpatemBuilder(const SpatemBuilder&) = delete;
  SpatemBuilder& operator=(const SpatemBuilder&) = delete;

  /// The SPATEM of @p states' groups of this intersection (others are ignored) at world-clock
  /// UTC @p now_ms: moy and timeStamp from @p now_ms, one MovementEvent per group with
  /// minEndTime = next_change_ms and likelyTime = likely_change_ms as TimeMarks. The
  /// IntersectionState's revision counts state changes (mod 128). An intersection without
  /// groups in @p states gets status noValidSPATisAvailableAtThisTime and one group-less state
  /// list is impossible (SIZE(1..)), so: kNoGroups.
  enum class Error : std::uint8_t { kNoGroups, kEncode };
  Expected<std::span<const std::uint8_t>, Error> build(const wire::sim::SignalStates& states,
                                                       std::int64_t now_ms);
  /// The message of the last successful build().
  const messages::Spatem& last() const { return *spatem_; }
  std::uint16_t intersection_id() const { return intersection_id_; }

 private:
  std::uint16_t intersection_id_;
  std::unique_ptr<messages::Spatem> spatem_;
  std::vector<std::uint8_t> buffer_;
  std::vector<wire::sim::SignalGroupState> previous_;
  messages::MsgCount revision_ = 0;
};

}  // namespace tb::its::rsu
