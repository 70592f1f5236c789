#pragma once
/// @file Where in the GNSS period a pooled station's epochs fall.
///
/// A pooled station runs its CA checks when its fix arrives (its-station's CaService checks at
/// each fix and at the latest every T_CheckCamGen). With every station's epochs on whole
/// periods of sim time, a host's stations all check, and send their CAMs, in the same tick: a
/// burst of up to one CAM per station that the radio medium then handles frame by frame
/// (docs/scale-out.md, "The hop between media"). Real cars' checks are not in phase
/// (EN 302 637-2 §6.1.3 fixes only the period). So each station gets its own offset of the
/// epoch grid, from its station id alone, so that a run repeats.

#include <chrono>
#include <cstdint>

namespace tb::host {

/// The offset in [0, @p period) of station @p station_id's epochs: the fractional part of
/// station_id × (golden ratio − 1), scaled to the period (Fibonacci hashing). Consecutive ids,
/// or ids with any common step, land far apart and fill the period evenly: among n stations no
/// two are closer than about period / (3n) apart, where random offsets would clump.
std::chrono::nanoseconds epoch_phase(std::uint32_t station_id, std::chrono::nanoseconds period);

}  // namespace tb::host
