#pragma once
/// @file The narrow port through which applications raise DENMs.
///
/// Applications sit above the facilities layer but must not depend on how the DEN service is
/// built, and tests replace it with a recorder. The station program hands an implementation
/// (an adapter over the facilities' DEN service) to the applications that need one. Field names
/// follow the DENM management container (EN 302 637-3, 7.1.2 and the CDD, TS 102 894-2).

#include <chrono>
#include <cstdint>
#include <optional>
#include <string_view>

#include "common/clock/clock.hpp"
#include "common/geodesy/wgs84.hpp"

namespace tb::its::apps {

/// CDD RelevanceDistance.
enum class RelevanceDistance : std::uint8_t {
  kLessThan50m = 0,
  kLessThan100m = 1,
  kLessThan200m = 2,
  kLessThan500m = 3,
  kLessThan1000m = 4,
  kLessThan5km = 5,
  kLessThan10km = 6,
  kOver10km = 7,
};

/// CDD RelevanceTrafficDirection.
enum class RelevanceTrafficDirection : std::uint8_t {
  kAllTrafficDirections = 0,
  kUpstreamTraffic = 1,
  kDownstreamTraffic = 2,
  kOppositeTraffic = 3,
};

/// CDD CauseCodeType collisionRisk and its sub-cause longitudinalCollisionRisk.
inline constexpr std::uint8_t kCauseCollisionRisk = 97;
inline constexpr std::uint8_t kSubCauseLongitudinalCollisionRisk = 1;

/// DENM ActionID: the same across repetitions and updates of one event (EN 302 637-3, 8.1).
struct ActionId {
  std::uint32_t originating_station_id = 0;
  std::uint16_t sequence_number = 0;
  friend bool operator==(const ActionId&, const ActionId&) = default;
};

struct DenEventRequest {
  std::uint8_t cause_code = kCauseCollisionRisk;
  std::uint8_t sub_cause_code = kSubCauseLongitudinalCollisionRisk;
  geodesy::Geodetic event_position;
  /// ETSI heading of the event (clockwise from north), degrees, when it has one.
  std::optional<double> event_heading_deg;
  clock::WallTime detection_time{};
  RelevanceDistance relevance_distance = RelevanceDistance::kLessThan100m;
  RelevanceTrafficDirection relevance_traffic_direction =
      RelevanceTrafficDirection::kAllTrafficDirections;
  /// CDD ValidityDuration; the DEN service's default is 600 s.
  std::chrono::seconds validity_duration{600};
  /// CDD InformationQuality, 0 (unavailable) … 7 (highest).
  std::uint8_t information_quality = 0;
  /// GN traffic class ID: 1 for DENMs, 0 for time-critical warnings (the C-ITS service
  /// profiles; see the facilities' DenRequest::traffic_class).
  std::uint8_t traffic_class = 1;
};

/// Implemented over the facilities' DEN service (EN 302 637-3 application requests
/// AppDENM_trigger, AppDENM_update and AppDENM_termination, clause 6.1.1).
class DenService {
 public:
  virtual ~DenService() = default;
  /// A new event; returns its ActionID, or nothing if the service refused it.
  virtual std::optional<ActionId> trigger(const DenEventRequest& request) = 0;
  /// New content for an event this station originated; false if the ActionID is unknown.
  virtual bool update(const ActionId& id, const DenEventRequest& request) = 0;
  /// Ends an event this station originated (a cancellation DENM); false if unknown.
  virtual bool terminate(const ActionId& id) = 0;
};

}  // namespace tb::its::apps
