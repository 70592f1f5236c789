// DEN service (EN 302 637-3 V1.3.1) seen from the receivers: three stations on an in-memory
// medium that delivers every DENM to every other station, with a manual clock.

#include <gtest/gtest.h>

#include <array>
#include <memory>

#include "its-station/facilities/den_service.hpp"
#include "its-station/facilities/its_time.hpp"
#include "its-station/facilities/tests/test_support.hpp"

namespace tb::its::facilities {
namespace {

using namespace std::chrono_literals;
using testing::RecordingSender;
using testing::SentPacket;

/// Inside the relevance area unless told otherwise.
struct SwitchableLocator final : AreaLocator {
  bool inside(const GeoArea&) const override { return in; }
  bool in = true;
};

DenConfig config_for(messages::StationID id, bool kaf) {
  DenConfig c;
  c.station_id = id;
  c.keep_alive_forwarding = kaf;
  // T_Forwarding's random part, fixed per station so that the test knows who forwards first.
  c.kaf_jitter = [id] { return std::chrono::milliseconds{id % 100}; };
  return c;
}

DenmReception reception(std::optional<GeoArea> area, std::uint8_t traffic_class,
                        std::optional<std::span<const std::uint8_t>> ssp = std::nullopt) {
  DenmReception rx;
  rx.destination_area = std::move(area);
  rx.traffic_class = traffic_class;
  rx.ssp = ssp;
  return rx;
}

struct Station {
  Station(clock::ManualRuntime& rt, messages::StationID id, bool kaf)
      : ldm(rt), den(rt, sender, ldm, config_for(id, kaf), &locator) {
    ldm.on_event([this](const Event& e, DenmOutcome o) {
      seen.push_back({e.denm.denm.management.actionID.sequenceNumber, o});
    });
  }
  RecordingSender sender;
  SwitchableLocator locator;
  Ldm ldm;
  DenService den;
  std::vector<std::pair<int, DenmOutcome>> seen;
  bool deaf = false;  ///< out of radio range: receives nothing
  /// DENMs this station sent, decoded.
  std::vector<messages::Denm> sent() const {
    std::vector<messages::Denm> out;
    for (const auto& p : sender.packets)
      if (auto d = messages::decode_denm(p.payload))
        out.push_back(*d);
    return out;
  }
};

/// Three stations (101, 202, 303) on a medium that delivers every DENM to every other station,
/// with the GeoBroadcast's area and traffic class; keep-alive forwarding off unless kaf().
class DenTest : public ::testing::Test {
 protected:
  void SetUp() override { make(false); }
  void make(bool kaf) {
    stations.clear();
    for (messages::StationID id : {101u, 202u, 303u})
      stations.push_back(std::make_unique<Station>(rt, id, kaf));
    for (auto& s : stations) {
      Station* from = s.get();
      s->sender.forward = [this, from](const SentPacket& p) {
        for (auto& to : stations)
          if (to.get() != from && !to->deaf)
            to->den.receive(p.payload, reception(p.area, p.traffic_class));
      };
    }
  }
  Station& a() { return *stations[0]; }
  Station& b() { return *stations[1]; }
  Station& c() { return *stations[2]; }

  DenRequest collision_risk() {
    DenRequest r;
    r.event_type = {messages::cause_code::kCollisionRisk,
                    messages::collision_risk_sub_cause::kLongitudinalCollisionRisk};
    r.information_quality = 3;
    r.event_latitude_deg = 48.001;
    r.event_longitude_deg = 11.002;
    r.relevance_distance = messages::RelevanceDistance::lessThan200m;
    r.repetition_interval = 100ms;
    r.repetition_duration = 1s;
    r.validity_s = 10;
    r.destination_area = GeoArea{GeoArea::Shape::kCircle, 48.001, 11.002, 200.0, 200.0, 0.0};
    return r;
  }

  clock::ManualRuntime rt;
  std::vector<std::unique_ptr<Station>> stations;
};

TEST_F(DenTest, TriggerIsGeoBroadcastAndRepeatedForItsDuration) {
  auto id = a().den.trigger(collision_risk());
  ASSERT_TRUE(id);
  EXPECT_EQ(id->originatingStationID, 101u);
  ASSERT_EQ(a().sender.packets.size(), 1u);
  const auto p = a().sender.packets[0];  // a copy: the vector grows below
  EXPECT_EQ(p.port, kBtpPortDenm);
  ASSERT_TRUE(p.area);
  EXPECT_DOUBLE_EQ(p.area->distance_a_m, 200.0);
  EXPECT_EQ(p.lifetime_ms, 10'000u);

  const auto* e = b().ldm.event(*id);
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->denm.denm.situation->eventType.causeCode, 97);
  EXPECT_EQ(e->denm.denm.management.transmissionInterval, 100);

  // Repetitions at 100, 200, …, 1000 ms: 10 more, all with the same referenceTime, which the
  // receivers drop as repetitions.
  rt.advance(2s);
  EXPECT_EQ(a().sender.packets.size(), 11u);
  for (const auto& q : a().sender.packets)
    EXPECT_EQ(q.payload, p.payload);
  EXPECT_EQ(b().den.counters().received, 11u);
  EXPECT_EQ(b().den.counters().dropped, 10u);
  EXPECT_EQ(b().seen, (std::vector<std::pair<int, DenmOutcome>>{{0, DenmOutcome::kNew}}));
}

TEST_F(DenTest, UpdateReplacesAndCancellationRemoves) {
  auto id = a().den.trigger(collision_risk());
  ASSERT_TRUE(id);
  rt.advance(250ms);
  auto req = collision_risk();
  req.information_quality = 6;
  ASSERT_TRUE(a().den.update(*id, req));
  const auto* e = b().ldm.event(*id);
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->denm.denm.situation->informationQuality, 6);
  rt.advance(250ms);
  ASSERT_TRUE(a().den.terminate(*id));
  EXPECT_EQ(b().ldm.event(*id), nullptr);
  EXPECT_TRUE(b().ldm.active_events().empty());
  EXPECT_EQ(a().sender.packets.back().payload.size() > 0, true);
  auto last = messages::decode_denm(a().sender.packets.back().payload);
  ASSERT_TRUE(last);
  EXPECT_EQ(last->denm.management.termination, messages::Termination::isCancellation);
  // The cancellation is repeated for the rest of the repetition duration and then stops;
  // its repetitions (same referenceTime) change nothing at the receivers.
  const auto sent_before = a().sender.packets.size();
  rt.advance(3s);
  EXPECT_GT(a().sender.packets.size(), sent_before);
  const auto sent_after = a().sender.packets.size();
  rt.advance(3s);
  EXPECT_EQ(a().sender.packets.size(), sent_after);
  EXPECT_EQ(a().den.originated(), 0u);
  EXPECT_EQ(b().seen,
            (std::vector<std::pair<int, DenmOutcome>>{
                {0, DenmOutcome::kNew}, {0, DenmOutcome::kUpdate}, {0, DenmOutcome::kCancelled}}));
  EXPECT_FALSE(a().den.update(*id, req));
  EXPECT_EQ(a().den.terminate(*id).error(), DenError::kUnknownAction);
}

TEST_F(DenTest, NegationByAnotherStationRemovesTheEventEverywhere) {
  auto id = a().den.trigger(collision_risk());
  ASSERT_TRUE(id);
  rt.advance(150ms);
  ASSERT_NE(c().ldm.event(*id), nullptr);
  // B finds the event is gone and negates it: same action ID, isNegation.
  auto neg = b().den.terminate(*id);
  ASSERT_TRUE(neg);
  auto sent = messages::decode_denm(b().sender.packets.back().payload);
  ASSERT_TRUE(sent);
  EXPECT_EQ(sent->header.stationID, 202u);
  EXPECT_EQ(sent->denm.management.actionID, (messages::ActionID{101, 0}));
  EXPECT_EQ(sent->denm.management.termination, messages::Termination::isNegation);
  // The negation keeps the event's referenceTime and dates itself by detectionTime.
  const auto original = messages::decode_denm(a().sender.packets.front().payload);
  ASSERT_TRUE(original);
  EXPECT_EQ(sent->denm.management.referenceTime, original->denm.management.referenceTime);
  EXPECT_EQ(sent->denm.management.detectionTime,
            static_cast<messages::TimestampIts>(timestamp_its(rt.wall_now())));
  EXPECT_GT(sent->denm.management.detectionTime, original->denm.management.detectionTime);
  EXPECT_EQ(c().ldm.event(*id), nullptr);
  EXPECT_EQ(b().ldm.event(*id), nullptr);
  // A stops repeating its negated event; later repetitions already in flight would be older
  // than the negation and stay dropped.
  const auto n = a().sender.packets.size();
  rt.advance(2s);
  EXPECT_EQ(a().sender.packets.size(), n);
  EXPECT_EQ(a().den.originated(), 0u);
  EXPECT_EQ(c().seen, (std::vector<std::pair<int, DenmOutcome>>{{0, DenmOutcome::kNew},
                                                                {0, DenmOutcome::kNegated}}));
}

TEST_F(DenTest, SequenceNumbersIdentifyEventsAndValidityExpires) {
  auto r = collision_risk();
  r.repetition_interval.reset();  // sent once
  auto first = a().den.trigger(r);
  auto second = a().den.trigger(r);
  ASSERT_TRUE(first && second);
  EXPECT_EQ(first->sequenceNumber, 0);
  EXPECT_EQ(second->sequenceNumber, 1);
  EXPECT_EQ(b().ldm.active_events().size(), 2u);
  EXPECT_EQ(a().sender.packets.size(), 2u);
  rt.advance(9s);
  EXPECT_EQ(b().ldm.active_events().size(), 2u);
  rt.advance(1s + 200ms);  // validity 10 s is over
  EXPECT_TRUE(b().ldm.active_events().empty());
  EXPECT_EQ(a().den.originated(), 0u);
  EXPECT_EQ(a().sender.packets.size(), 2u);
}

TEST_F(DenTest, ValidityBeyondTheGnMaximumIsSentWithTheLifetimeCapped) {
  auto r = collision_risk();
  r.validity_s = 3600;
  ASSERT_TRUE(a().den.trigger(r));
  ASSERT_FALSE(a().sender.packets.empty());
  EXPECT_EQ(a().sender.packets.back().lifetime_ms, 600'000u);  // itsGnMaxPacketLifetime
  r.validity_s = 10;
  ASSERT_TRUE(a().den.trigger(r));
  EXPECT_EQ(a().sender.packets.back().lifetime_ms, 10'000u);
}

TEST_F(DenTest, ATransmitTheNetworkRefusesIsReportedAsAFailure) {
  a().sender.result = SendResult::kNoPosition;
  const auto id = a().den.trigger(collision_risk());
  ASSERT_FALSE(id);
  EXPECT_EQ(id.error(), DenError::kSendFailed);
  EXPECT_EQ(a().den.originated(), 0u);
  EXPECT_EQ(a().den.counters().sent, 0u);
  EXPECT_EQ(a().den.counters().send_errors, 1u);
  a().sender.result = SendResult::kSent;
  const auto ok = a().den.trigger(collision_risk());
  ASSERT_TRUE(ok);
  a().sender.result = SendResult::kLinkError;
  const auto up = a().den.update(*ok, collision_risk());
  ASSERT_FALSE(up);
  EXPECT_EQ(up.error(), DenError::kSendFailed);
  const auto end = a().den.terminate(*ok);
  ASSERT_FALSE(end);
  EXPECT_EQ(end.error(), DenError::kSendFailed);
}

TEST_F(DenTest, BadRequestsAreRefused) {
  auto r = collision_risk();
  r.validity_s = 90000;
  EXPECT_EQ(a().den.trigger(r).error(), DenError::kBadRequest);
  r = collision_risk();
  r.event_latitude_deg = 95.0;
  EXPECT_EQ(a().den.trigger(r).error(), DenError::kBadRequest);
  r = collision_risk();
  r.repetition_interval = 20s;
  EXPECT_EQ(a().den.trigger(r).error(), DenError::kBadRequest);
  EXPECT_TRUE(a().sender.packets.empty());
  EXPECT_EQ(b().den.terminate({999, 1}).error(), DenError::kUnknownAction);
}

TEST_F(DenTest, ASignedDenmNeedsItsCauseCodesSspBit) {
  for (auto& s : stations)
    s->sender.forward = nullptr;  // carried by hand below
  auto id = a().den.trigger(collision_risk());
  ASSERT_TRUE(id);
  const auto payload = a().sender.packets[0].payload;
  const std::array<std::uint8_t, 4> no_collision_risk{0x01, 0xff, 0xff, 0xfb};
  b().den.receive(payload, reception(std::nullopt, kDenmTrafficClassDefault, no_collision_risk));
  EXPECT_EQ(b().den.counters().not_permitted, 1u);
  EXPECT_EQ(b().ldm.event(*id), nullptr);
  const std::array<std::uint8_t, 4> all{0x01, 0xff, 0xff, 0xff};  // its-pki's
  b().den.receive(payload, reception(std::nullopt, kDenmTrafficClassDefault, all));
  EXPECT_NE(b().ldm.event(*id), nullptr);
  EXPECT_EQ(b().den.counters().received, 1u);
}

TEST_F(DenTest, TrafficClassComesFromTheRequest) {
  auto r = collision_risk();
  r.repetition_interval.reset();
  ASSERT_TRUE(a().den.trigger(r));
  EXPECT_EQ(a().sender.packets.back().traffic_class, kDenmTrafficClassDefault);
  r.traffic_class = kDenmTrafficClassTimeCritical;
  const auto id = a().den.trigger(r);
  ASSERT_TRUE(id);
  EXPECT_EQ(a().sender.packets.back().traffic_class, 0);
  // A negation is no time-critical warning: the default class.
  ASSERT_TRUE(b().den.terminate(*id));
  EXPECT_EQ(b().sender.packets.back().traffic_class, kDenmTrafficClassDefault);
}

// Keep-alive forwarding (EN 302 637-3 clause 8.2.2; TS 102 869-2 TP/DEN/KAFW). A repeats its
// event every 100 ms for 1 s (transmissionInterval 100); T_Forwarding is then
// 2 × 100 ms + the station's jitter (config_for: B 2 ms, C 3 ms).
TEST_F(DenTest, KeepAliveForwardingCarriesASilentOriginatorsEvent) {
  make(true);
  const auto id = a().den.trigger(collision_risk());
  ASSERT_TRUE(id);
  const messages::Denm original = a().sent().front();
  // While A repeats, every repetition restarts B's and C's timers: nobody forwards.
  rt.advance(1000ms);
  EXPECT_EQ(b().den.counters().forwarded, 0u);
  EXPECT_EQ(c().den.counters().forwarded, 0u);
  EXPECT_EQ(b().den.keeping_alive(), 1u);
  // A's last DENM left at 1000 ms. B's timer runs out first (1202 ms); its forwarding restarts
  // C's, so B alone keeps the event alive, every 202 ms.
  rt.advance(201ms);
  EXPECT_EQ(b().den.counters().forwarded, 0u);
  rt.advance(1ms);
  EXPECT_EQ(b().den.counters().forwarded, 1u);
  rt.advance(798ms);  // 2000 ms: forwardings at 1202, 1404, 1606, 1808
  EXPECT_EQ(b().den.counters().forwarded, 4u);
  EXPECT_EQ(c().den.counters().forwarded, 0u);
  // What B sends is A's DENM with B's header: action ID, referenceTime, every container as A
  // sent them (BV-04 … BV-08), into A's area with A's traffic class.
  const auto fwd = b().sent();
  ASSERT_EQ(fwd.size(), 4u);
  messages::Denm expected = original;
  expected.header.stationID = 202;
  for (const auto& d : fwd)
    EXPECT_EQ(d, expected);
  EXPECT_EQ(b().sender.packets.back().area, a().sender.packets.front().area);
  EXPECT_EQ(b().sender.packets.back().traffic_class, a().sender.packets.front().traffic_class);
  // A hears its own event from B and keeps out of it; C's copy stays the one A sent.
  EXPECT_EQ(a().den.counters().own_heard, 4u);
  EXPECT_EQ(a().ldm.event(*id), nullptr);
  EXPECT_EQ(c().seen, (std::vector<std::pair<int, DenmOutcome>>{{0, DenmOutcome::kNew}}));
  EXPECT_NE(c().ldm.event(*id), nullptr);

  // B leaves the relevance area (BV-10): it stops at its next expiry (2010 ms); C's timer, last
  // restarted by B at 1808 ms, then runs out at 2011 ms, and C carries on every 203 ms.
  b().locator.in = false;
  rt.advance(10ms);
  EXPECT_EQ(b().den.counters().forwarded, 4u);
  EXPECT_EQ(b().den.keeping_alive(), 0u);
  rt.advance(1ms);
  EXPECT_EQ(c().den.counters().forwarded, 1u);
  EXPECT_EQ(c().sent().back().header.stationID, 303u);

  // The validity (10 s from detection at 0) ends forwarding (BV-09): the last timer is cut to
  // the end of the validity, which sends nothing.
  rt.advance(8000ms);
  const auto at_10s = c().den.counters().forwarded;
  EXPECT_EQ(at_10s, 40u);  // 2011 + 203 k ≤ 10000 ms: k = 0 … 39
  rt.advance(2000ms);
  EXPECT_EQ(c().den.counters().forwarded, at_10s);
  EXPECT_EQ(c().den.keeping_alive(), 0u);
}

TEST_F(DenTest, NoKeepAliveWithoutTransmissionIntervalOrBeyondTheValidity) {
  make(true);
  auto r = collision_risk();
  r.repetition_interval.reset();  // sent once, no transmissionInterval (BV-11)
  ASSERT_TRUE(a().den.trigger(r));
  EXPECT_EQ(b().den.keeping_alive(), 0u);
  rt.advance(5s);
  EXPECT_EQ(b().den.counters().forwarded + c().den.counters().forwarded, 0u);

  // T_Forwarding = min(2 × 1000 ms + jitter, validity left): a DENM valid for 1 s is not
  // forwarded at all (TI-03, BV-09).
  r.repetition_interval = 1000ms;
  r.repetition_duration = 0ms;
  r.validity_s = 1;
  ASSERT_TRUE(a().den.trigger(r));
  EXPECT_EQ(b().den.keeping_alive(), 1u);
  rt.advance(1100ms);
  EXPECT_EQ(b().den.counters().forwarded + c().den.counters().forwarded, 0u);
  EXPECT_EQ(b().den.keeping_alive(), 0u);
}

TEST_F(DenTest, AnOlderVersionDoesNotRestartTheForwardingTimer) {
  make(true);
  c().deaf = true;  // B alone keeps A's event alive
  auto r = collision_risk();
  r.repetition_duration = 0ms;  // A sends once, with transmissionInterval 100
  const auto id = a().den.trigger(r);
  ASSERT_TRUE(id);
  const messages::Denm first = a().sent().front();
  rt.advance(50ms);
  // An update at 50 ms ...
  ASSERT_TRUE(a().den.update(*id, r));
  const messages::Denm second = a().sent().back();
  ASSERT_GT(second.denm.management.referenceTime, first.denm.management.referenceTime);
  // ... then a late copy of the first version, from a third station, at 100 ms: older than
  // what B holds, so no sign that anyone keeps the event alive (BV-02).
  rt.advance(50ms);
  messages::Denm late = first;
  late.header.stationID = 404;
  b().den.receive(*messages::encode(late));
  EXPECT_EQ(b().den.counters().dropped, 1u);
  // B forwards the second version 202 ms after it arrived (at 252 ms), not after the late one.
  rt.advance(151ms);
  EXPECT_EQ(b().den.counters().forwarded, 0u);
  rt.advance(1ms);
  ASSERT_EQ(b().den.counters().forwarded, 1u);
  EXPECT_EQ(b().sent().back().denm.management.referenceTime, second.denm.management.referenceTime);
}

TEST_F(DenTest, AForwardedTerminationKeepsItsTermination) {
  make(true);
  c().deaf = true;
  auto r = collision_risk();
  r.repetition_duration = 300ms;
  const auto id = a().den.trigger(r);
  ASSERT_TRUE(id);
  rt.advance(150ms);
  ASSERT_TRUE(a().den.terminate(*id));  // cancellation, repeated until 300 ms
  EXPECT_EQ(b().ldm.event(*id), nullptr);
  rt.advance(1s);
  ASSERT_GT(b().den.counters().forwarded, 0u);
  const auto fwd = b().sent().back();
  EXPECT_EQ(fwd.denm.management.termination, messages::Termination::isCancellation);
  EXPECT_EQ(fwd.header.stationID, 202u);
  // The originator hears its cancellation kept alive and stays out of it.
  EXPECT_GT(a().den.counters().own_heard, 0u);
}

TEST_F(DenTest, ForwardingTimerJitterIsWithinTheStandardsRange) {
  // Without an injected jitter: 2 × transmissionInterval + a uniform draw in [0, 150 ms].
  RecordingSender sender;
  Ldm ldm(rt);
  DenConfig cfg;
  cfg.station_id = 555;
  DenService den(rt, sender, ldm, cfg);
  auto r = collision_risk();
  r.repetition_duration = 0ms;
  r.repetition_interval = 500ms;
  ASSERT_TRUE(a().den.trigger(r));
  den.receive(a().sender.packets.back().payload);
  rt.advance(999ms);
  EXPECT_EQ(den.counters().forwarded, 0u);
  rt.advance(151ms);
  EXPECT_EQ(den.counters().forwarded, 1u);
}

TEST_F(DenTest, GarbageIsCountedAndDropped) {
  const std::uint8_t junk[] = {0x02, 0x01, 0x00};
  b().den.receive(junk);
  EXPECT_EQ(b().den.counters().decode_errors, 1u);
  EXPECT_TRUE(b().ldm.active_events().empty());
}

}  // namespace
}  // namespace tb::its::facilities
