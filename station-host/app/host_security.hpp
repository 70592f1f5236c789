#pragma once
/// @file A pooled station's security entity, from its own its-pki export directory.

#include <cstdint>
#include <filesystem>
#include <memory>

#include "common/scenario/scenario.hpp"
#include "its-station/security/security_entity.hpp"

namespace tb::host {

/// The entity of station @p station_id: its AT and key, the AA and root from @p dir (what
/// `its-pki export` writes for a full station), the generation-time windows of the scenario
/// over the defaults. Null when the scenario does not sign. @throws ConfigError naming the
/// directory and what is wrong with it.
std::unique_ptr<its::security::SecurityEntity> make_station_security(
    const scenario::Scenario& scenario, const std::filesystem::path& dir, std::uint32_t station_id);

}  // namespace tb::host
