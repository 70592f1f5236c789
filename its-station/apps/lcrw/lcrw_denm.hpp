#pragma once
/// @file Raises a collision-risk DENM (cause 97, sub-cause longitudinalCollisionRisk) for every
/// active LCRW warning, so that the other vehicle's driver learns of the risk too.

#include <cstdint>
#include <map>

#include "common/geodesy/local_frame.hpp"
#include "its-station/apps/den/den_port.hpp"
#include "its-station/apps/lcrw/lcrw.hpp"

namespace tb::its::apps {

struct LcrwDenmConfig {
  /// Raise DENMs only for critical warnings (TTC below ttc_critical_s) instead of all.
  bool only_critical = false;
  std::chrono::seconds validity_duration{10};
};

class LcrwDenmTrigger {
 public:
  LcrwDenmTrigger(DenService& den, const geodesy::LocalFrame& frame, LcrwDenmConfig cfg = {});

  /// Feeds one event of Lcrw::evaluate(); @p own is the own vehicle it was computed for (the
  /// event position is the detecting vehicle's position).
  void on_warning(const LcrwWarning& w, const VehicleKinematics& own);

  /// The open events, by other station id.
  const std::map<std::uint32_t, ActionId>& open_events() const { return open_; }

  /// Added to the gap before choosing the relevance distance (request_for()).
  static constexpr double kRelevanceMarginM = 20.0;
  /// Relevance distance for a distance: the smallest CDD class that holds it.
  static RelevanceDistance relevance_for(double distance_m);

 private:
  DenEventRequest request_for(const LcrwWarning& w, const VehicleKinematics& own) const;

  DenService& den_;
  const geodesy::LocalFrame& frame_;
  LcrwDenmConfig cfg_;
  std::map<std::uint32_t, ActionId> open_;
  struct Sent {
    Severity severity;
    RelevanceDistance relevance;
  };
  std::map<std::uint32_t, Sent> sent_;
};

}  // namespace tb::its::apps
