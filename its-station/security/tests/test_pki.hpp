#pragma once
// A test PKI in memory for tests of the layers that use the security entity: a root, an AA, and
// security entities with ATs of their own, valid around @p now.

#include <memory>

#include <gtest/gtest.h>

#include "its-station/security/pki.hpp"
#include "its-station/security/security_entity.hpp"
#include "its-station/security/time.hpp"

namespace tb::its::security::testing {

struct TestPki {
  clock::WallTime now;
  Time32 start = to_time32(now) - 3600;
  EcKey root_key = EcKey::generate(EccCurve::kNistP256);
  EcKey aa_key = EcKey::generate(EccCurve::kNistP256);
  Certificate root = make_root(root_key, "root", {start, DurationUnit::kHours, 100});
  Certificate aa = make_authority(aa_key, "aa", {start, DurationUnit::kHours, 100}, root, root_key);

  /// An entity with an AT of its own. @p strip_gn_mgmt: an AT of an older its-pki, without the
  /// GN-MGMT permission.
  std::unique_ptr<SecurityEntity> entity(SecurityMode mode, bool strip_gn_mgmt = false) {
    EcKey k = EcKey::generate(EccCurve::kNistP256);
    Certificate at = make_ticket(k, {start, DurationUnit::kHours, 10}, aa, aa_key);
    if (strip_gn_mgmt) {
      at.tbs.app_permissions->pop_back();
      sign_certificate(at, &aa, aa_key);
    }
    Verifier v({root});
    EXPECT_EQ(v.add_authority(aa, to_time64(now)), VerifyResult::kOk);
    return std::make_unique<SecurityEntity>(mode, Signer(std::move(at), std::move(k), aa),
                                            std::move(v));
  }
};

}  // namespace tb::its::security::testing
