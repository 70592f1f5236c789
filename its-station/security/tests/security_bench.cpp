// Signing and verification times of issue 20: sign <= 30 us, verify <= 60 us (medians), a CAM
// with a digest signer costing one ECDSA verify once its AT is known; and the sizes of a signed
// CAM. The payload is what socktap signs: GN common header, SHB, BTP-B and a 46-byte CAM
// (81 octets). Run with --benchmark_repetitions=10 or more.

#include <benchmark/benchmark.h>

#include "its-station/security/pki.hpp"
#include "its-station/security/security_entity.hpp"
#include "its-station/security/time.hpp"

namespace tb::its::security {
namespace {

const Time64 kNow = to_time64(clock::WallTime{std::chrono::seconds(1795454308)});
const Time32 kNowS = static_cast<Time32>(kNow / 1000000);
const Bytes kPayload(81, 0x5a);

struct World {
  EcKey root_key = EcKey::generate(EccCurve::kNistP256);
  EcKey aa_key = EcKey::generate(EccCurve::kNistP256);
  Certificate root = make_root(root_key, "root", {kNowS - 3600, DurationUnit::kHours, 100});
  Certificate aa =
      make_authority(aa_key, "aa", {kNowS - 3600, DurationUnit::kHours, 100}, root, root_key);
  Signer signer() {
    EcKey k = EcKey::generate(EccCurve::kNistP256);
    Certificate at = make_ticket(k, {kNowS - 60, DurationUnit::kHours, 10}, aa, aa_key);
    return Signer(std::move(at), std::move(k), aa);
  }
  Verifier verifier(VerifierConfig cfg = {}) {
    Verifier v({root}, cfg);
    v.add_authority(aa, kNow);
    return v;
  }
};

World& world() {
  static World w;
  return w;
}

void BM_EcdsaP256Sign(benchmark::State& state) {
  EcKey k = EcKey::generate(EccCurve::kNistP256);
  const Octets32 digest = sha256(kPayload);
  for (auto _ : state)
    benchmark::DoNotOptimize(k.sign(digest));
}
BENCHMARK(BM_EcdsaP256Sign);

void BM_EcdsaVerify(benchmark::State& state, EccCurve curve) {
  EcKey k = EcKey::generate(curve);
  EcKey pub = EcKey::from_point(curve, k.public_point());
  const Octets32 digest = sha256(kPayload);
  const Signature sig = k.sign(digest);
  for (auto _ : state)
    benchmark::DoNotOptimize(pub.verify(digest, sig));
}
BENCHMARK_CAPTURE(BM_EcdsaVerify, p256, EccCurve::kNistP256);
BENCHMARK_CAPTURE(BM_EcdsaVerify, brainpoolP256r1, EccCurve::kBrainpoolP256r1);

/// A whole signed CAM: tbsData encoding, both hashes, ECDSA, the Ieee1609Dot2Data encoding.
void BM_SignCam(benchmark::State& state, bool with_certificate) {
  Signer s = world().signer();
  Bytes out;
  for (auto _ : state) {
    out = s.sign(kPsidCam, kPayload, kNow, std::nullopt, with_certificate);
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["bytes"] = static_cast<double>(out.size());
  state.counters["overhead"] = static_cast<double>(out.size() - kPayload.size());
}
BENCHMARK_CAPTURE(BM_SignCam, digest, false);
BENCHMARK_CAPTURE(BM_SignCam, certificate, true);

/// Verification of a CAM whose AT the verifier knows (cached): decode, hashes, one verify, and
/// (issue 31) the replay table's look-up and insertion. Each packet is new (signed outside the
/// timing, 1 ms after the last), as on the air: the same octets again would be a replay.
/// @p replay_detection false: the same without the table, to show what it costs.
void BM_VerifyCamCached(benchmark::State& state, bool with_certificate, bool replay_detection) {
  Signer s = world().signer();
  VerifierConfig cfg;
  cfg.time_policy[kPsidCam] = default_time_policy(kPsidCam);
  cfg.time_policy[kPsidCam].replay_detection = replay_detection;
  Verifier v = world().verifier(cfg);
  const Bytes first = s.sign(kPsidCam, kPayload, kNow, std::nullopt, true);
  if (v.verify(first, kPsidCam, kNow).result != VerifyResult::kOk) {
    state.SkipWithError("the first CAM does not verify");
    return;
  }
  Time64 now = kNow;
  for (auto _ : state) {
    state.PauseTiming();
    now += 1000;
    const Bytes packet = s.sign(kPsidCam, kPayload, now, std::nullopt, with_certificate);
    state.ResumeTiming();
    auto r = v.verify(packet, kPsidCam, now);
    benchmark::DoNotOptimize(r.result);
    if (r.result != VerifyResult::kOk) {
      state.SkipWithError("a CAM does not verify");
      return;
    }
  }
}
BENCHMARK_CAPTURE(BM_VerifyCamCached, digest, false, true);
BENCHMARK_CAPTURE(BM_VerifyCamCached, certificate, true, true);
BENCHMARK_CAPTURE(BM_VerifyCamCached, digest_no_replay_table, false, false);

/// A CAM with an AT the verifier has not seen: the AT's signature by the AA, then the CAM's.
void BM_VerifyCamNewTicket(benchmark::State& state) {
  Signer s = world().signer();
  const Bytes packet = s.sign(kPsidCam, kPayload, kNow, std::nullopt, true);
  for (auto _ : state) {
    state.PauseTiming();
    Verifier v = world().verifier();
    state.ResumeTiming();
    auto r = v.verify(packet, kPsidCam, kNow);
    benchmark::DoNotOptimize(r.result);
  }
}
BENCHMARK(BM_VerifyCamNewTicket);

/// A signed CAM received by a station's security entity (decapsulate: decode, checks, the
/// payload copied out), with every packet verified (a full station, and a pooled one running
/// LCRW) or verified on demand (a pooled station without a CAM consumer: issue 33). The sender's
/// AT is known; @p with_certificate: the CAM carries it (recognised by its hash). The CAMs are
/// signed outside the timing, 1024 at a time, each 1 ms after the last (no replays); on demand
/// keeps no state per packet (no replay table), so its batch is signed once and gone through
/// again (signing a new one per 1024 CAMs of ~0.2 µs made the run take minutes).
void BM_ReceiveCam(benchmark::State& state, VerifyPolicy policy, bool with_certificate) {
  Signer s = world().signer();
  SecurityEntity e(SecurityMode::kSigned, world().signer(), world().verifier());
  e.set_verify_policy(policy);
  Time64 now = kNow;
  if (e.decapsulate(s.sign(kPsidCam, kPayload, now, std::nullopt, true), now).at(0).reason ==
      VerifyResult::kUnknownIssuer) {
    state.SkipWithError("the first CAM's AT is not known");
    return;
  }
  const VerifyResult expected =
      policy == VerifyPolicy::kEvery ? VerifyResult::kOk : VerifyResult::kNotVerified;
  std::vector<std::pair<Time64, Bytes>> batch;
  std::size_t next = 0;
  for (auto _ : state) {
    if (next == batch.size() && policy == VerifyPolicy::kOnDemand && !batch.empty()) {
      next = 0;
    } else if (next == batch.size()) {
      state.PauseTiming();
      batch.clear();
      for (int i = 0; i < 1024; ++i) {
        now += 1000;
        batch.emplace_back(now, s.sign(kPsidCam, kPayload, now, std::nullopt, with_certificate));
      }
      next = 0;
      state.ResumeTiming();
    }
    const auto& [at, packet] = batch[next++];
    auto out = e.decapsulate(packet, at);
    benchmark::DoNotOptimize(out.data());
    if (out.size() != 1 || out[0].reason != expected) {
      state.SkipWithError("a CAM does not give the policy's outcome");
      return;
    }
  }
}
BENCHMARK_CAPTURE(BM_ReceiveCam, every_digest, VerifyPolicy::kEvery, false);
BENCHMARK_CAPTURE(BM_ReceiveCam, on_demand_digest, VerifyPolicy::kOnDemand, false);
BENCHMARK_CAPTURE(BM_ReceiveCam, every_certificate, VerifyPolicy::kEvery, true);
BENCHMARK_CAPTURE(BM_ReceiveCam, on_demand_certificate, VerifyPolicy::kOnDemand, true);

}  // namespace
}  // namespace tb::its::security

BENCHMARK_MAIN();
