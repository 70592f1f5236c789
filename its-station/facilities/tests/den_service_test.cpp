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

struct Station {
  Station(clock::ManualRuntime& rt, messages::StationID id)
      : ldm(rt), den(rt, sender, ldm, DenConfig{id, messages::station_type::kPassengerCar}) {
    ldm.on_event([this](const Event& e, DenmOutcome o) {
      seen.push_back({e.denm.denm.management.actionID.sequenceNumber, o});
    });
  }
  RecordingSender sender;
  Ldm ldm;
  DenService den;
  std::vector<std::pair<int, DenmOutcome>> seen;
};

class DenTest : public ::testing::Test {
 protected:
  void SetUp() override {
    for (messages::StationID id : {101u, 202u, 303u})
      stations.push_back(std::make_unique<Station>(rt, id));
    for (auto& s : stations) {
      Station* from = s.get();
      s->sender.forward = [this, from](const SentPacket& p) {
        for (auto& to : stations)
          if (to.get() != from)
            to->den.receive(p.payload);
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
                {0, DenmOutcome::kNew}, {0, DenmOutcome::kUpdate}, {0, DenmOutcome::kTerminated}}));
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
                                                                {0, DenmOutcome::kTerminated}}));
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
  b().den.receive(payload, std::span<const std::uint8_t>(no_collision_risk));
  EXPECT_EQ(b().den.counters().not_permitted, 1u);
  EXPECT_EQ(b().ldm.event(*id), nullptr);
  const std::array<std::uint8_t, 4> all{0x01, 0xff, 0xff, 0xff};  // its-pki's
  b().den.receive(payload, std::span<const std::uint8_t>(all));
  EXPECT_NE(b().ldm.event(*id), nullptr);
  EXPECT_EQ(b().den.counters().received, 1u);
}

TEST_F(DenTest, GarbageIsCountedAndDropped) {
  const std::uint8_t junk[] = {0x02, 0x01, 0x00};
  b().den.receive(junk);
  EXPECT_EQ(b().den.counters().decode_errors, 1u);
  EXPECT_TRUE(b().ldm.active_events().empty());
}

}  // namespace
}  // namespace tb::its::facilities
