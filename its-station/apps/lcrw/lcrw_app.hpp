#pragma once
/// @file The LCRW application as the station runs it: at every own-vehicle update, evaluate the
/// neighbours, hand every warning event to the HMI side (MQTT) and, if wired, keep the
/// collision-risk DENMs in step.

#include <functional>
#include <span>

#include "its-station/apps/lcrw/lcrw.hpp"
#include "its-station/apps/lcrw/lcrw_denm.hpp"

namespace tb::its::apps {

class LcrwApplication {
 public:
  using WarningSink = std::function<void(const LcrwWarning&)>;

  /// @p denm may be null: warnings only, no DENMs.
  LcrwApplication(const clock::Clock& clock, LcrwConfig cfg, WarningSink sink,
                  LcrwDenmTrigger* denm = nullptr)
      : lcrw_(clock, cfg), sink_(std::move(sink)), denm_(denm) {}

  /// Returns the events of this evaluation (already forwarded).
  std::vector<LcrwWarning> update(const VehicleKinematics& own,
                                  std::span<const VehicleKinematics> neighbours) {
    std::vector<LcrwWarning> events = lcrw_.evaluate(own, neighbours);
    for (const LcrwWarning& w : events) {
      if (sink_) {
        sink_(w);
      }
      if (denm_ != nullptr) {
        denm_->on_warning(w, own);
      }
    }
    return events;
  }

  const Lcrw& lcrw() const { return lcrw_; }

 private:
  Lcrw lcrw_;
  WarningSink sink_;
  LcrwDenmTrigger* denm_;
};

}  // namespace tb::its::apps
