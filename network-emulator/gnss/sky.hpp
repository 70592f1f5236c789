#pragma once
/// @file The satellites a GPS agent reports, and the dilution of precision their geometry gives.
///
/// gpsd computes xdop/ydop (and from them epx/epy) from the azimuths and elevations of the
/// used satellites, but takes HDOP/VDOP/PDOP from the sentences. So that both tell the same
/// story, the sky is built so that its geometry has the HDOP the scenario asks for.

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "network-emulator/gnss/nmea.hpp"

namespace tb::emu::gnss {

struct Dop {
  double xdop = 0, ydop = 0, hdop = 0, vdop = 0, pdop = 0, tdop = 0, gdop = 0;
};

/// DOPs of the used satellites (east, north, up, receiver clock); empty with fewer than four
/// used satellites or a degenerate geometry.
std::optional<Dop> compute_dop(std::span<const SatelliteView> sky);

/// @p count satellites (4..32, at most 12 used), deterministic for a @p seed, whose geometry
/// gives an HDOP as close to @p target_hdop as this layout allows (roughly 0.6 to 8 for nine
/// satellites; outside that the nearest reachable value).
std::vector<SatelliteView> make_sky(int count, double target_hdop, std::uint64_t seed);

}  // namespace tb::emu::gnss
