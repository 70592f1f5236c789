#pragma once
/// @file The LCRW application as the station runs it: at every own-vehicle update, evaluate the
/// neighbours, hand every warning event to the HMI side (MQTT) and, if wired, keep the
/// collision-risk DENMs in step.

#include <functional>
#include <span>

#include "common/trace/tracer.hpp"
#include "its-station/apps/its_time.hpp"
#include "its-station/apps/lcrw/lcrw.hpp"
#include "its-station/apps/lcrw/lcrw_denm.hpp"

namespace tb::its::apps {

class LcrwApplication {
 public:
  using WarningSink = std::function<void(const LcrwWarning&)>;

  /// @p denm may be null: warnings only, no DENMs. @p tracer (may be null) receives an
  /// `its.lcrw` record per neighbour and evaluation (docs/tracing.md): station, from, gdt of
  /// the neighbour's CAM, warn, ttc.
  LcrwApplication(const clock::Clock& clock, LcrwConfig cfg, WarningSink sink,
                  LcrwDenmTrigger* denm = nullptr, trace::Tracer* tracer = nullptr)
      : lcrw_(clock, cfg), sink_(std::move(sink)), denm_(denm), tracer_(tracer) {}

  /// Returns the events of this evaluation (already forwarded).
  std::vector<LcrwWarning> update(const VehicleKinematics& own,
                                  std::span<const VehicleKinematics> neighbours) {
    std::vector<LcrwWarning> events = lcrw_.evaluate(own, neighbours);
    if (tracer_ != nullptr && tracer_->enabled()) {
      for (const VehicleKinematics& n : neighbours) {
        const auto a = lcrw_.last_assessments().find(n.station_id);
        if (a == lcrw_.last_assessments().end()) {
          continue;  // itself, or too old to assess
        }
        tracer_->record("its.lcrw", {{"station", own.station_id},
                                     {"from", n.station_id},
                                     {"gdt", generation_delta_time(n.time)},
                                     {"warn", lcrw_.active().contains(n.station_id)},
                                     {"ttc", a->second.ttc_s}});
      }
    }
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
  trace::Tracer* tracer_;
};

}  // namespace tb::its::apps
