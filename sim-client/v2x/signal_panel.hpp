#pragma once
/// @file What the driver's HUD shows of the own lane's signal and of the red-light violation
/// warning (issue 34): pure data made from the V2X picture, so that tests can say what is
/// shown for which messages without drawing, and the 3D HUD only lays it out.

#include <cstdint>
#include <optional>
#include <string>

#include "sim-client/v2x/monitor.hpp"

namespace tb::client::v2x {

/// The signal panel: a traffic-light icon and the figures beside it.
struct SignalPanel {
  std::uint32_t station = 0;
  std::uint32_t intersection_id = 0;
  std::uint32_t signal_group = 0;
  std::uint32_t lane_id = 0;
  SignalLight light = SignalLight::kUnavailable;
  /// Which of the icon's lamps are lit; none for dark and unavailable (the icon is grey).
  bool red = false, amber = false, green = false;
  /// Whole seconds to the next change: the likely time when the station knows one, else the
  /// minimum (minEndTime); rounded up, as countdown displays at junctions count, so that "0"
  /// is never shown before the change. Empty when neither is known.
  std::optional<int> countdown_s;
  bool countdown_is_likely = false;
  std::string countdown;  ///< "7 s", "" without a countdown
  std::string distance;   ///< "42 m" to the stop line
  /// GLOSA as a range of whole km/h inside the advised one ("32–45 km/h"), or one speed when
  /// the range holds no whole number's width; "" without advice.
  std::string advice;
  std::string caption;  ///< "group 3 · lane 2" (the signal group, the ingress lane)
};

/// The panel for @p station's own lane, while its signal is fresh; empty otherwise.
std::optional<SignalPanel> signal_panel(const V2xPicture& picture, std::uint32_t station);

/// The red-light warning banner's text for @p station, empty when none is active.
std::string rlvw_banner(const V2xPicture& picture, std::uint32_t station);

}  // namespace tb::client::v2x
