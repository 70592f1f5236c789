#include "station-host/app/host_security.hpp"

#include <fmt/format.h>

#include "its-station/security/pki_files.hpp"
#include "station-host/app/host_config.hpp"

namespace tb::host {

namespace sec = its::security;

std::unique_ptr<sec::SecurityEntity> make_station_security(const scenario::Scenario& scenario,
                                                           const std::filesystem::path& dir,
                                                           std::uint32_t station_id) {
  sec::SecurityMode mode = sec::SecurityMode::kNone;
  switch (scenario.security) {
    case scenario::SecurityMode::kNone:
      return nullptr;
    case scenario::SecurityMode::kSigned:
      mode = sec::SecurityMode::kSigned;
      break;
    case scenario::SecurityMode::kSignedPermissive:
      mode = sec::SecurityMode::kSignedPermissive;
      break;
  }
  // The same windows as its-station gives a full station of this scenario.
  sec::VerifierConfig config;
  for (const auto& [psid, w] : scenario.security_time_windows) {
    sec::TimePolicy p = sec::default_time_policy(psid);
    if (w.past_ms)
      p.past = std::chrono::milliseconds(*w.past_ms);
    if (w.future_ms)
      p.future = std::chrono::milliseconds(*w.future_ms);
    config.time_policy[psid] = p;
  }
  try {
    auto creds = sec::load_station_credentials(sec::PkiPaths{dir}, station_id);
    sec::Verifier verifier({creds.root}, config);
    // The chain is checked here, the validity per packet on the ITS clock (as its-station).
    const auto aa = verifier.add_authority(
        creds.aa, static_cast<sec::Time64>(creds.aa.tbs.validity.start) * 1'000'000);
    if (aa != sec::VerifyResult::kOk)
      throw ConfigError(fmt::format("--pki-dir {}: the AA does not verify under the root: {}",
                                    dir.string(), sec::to_string(aa)));
    auto entity = std::make_unique<sec::SecurityEntity>(
        mode, sec::Signer(std::move(creds.at), std::move(creds.at_key), creds.aa),
        std::move(verifier));
    entity->set_trace_station(station_id);
    return entity;
  } catch (const sec::PkiFileError& e) {
    throw ConfigError(fmt::format("--pki-dir, station {}: {}", station_id, e.what()));
  } catch (const sec::CryptoError& e) {
    throw ConfigError(fmt::format("--pki-dir, station {}: {}", station_id, e.what()));
  }
}

}  // namespace tb::host
