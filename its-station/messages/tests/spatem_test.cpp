// SPATEM (TS 103 301 v2.1.1, ISO TS 19091 SPAT): a worked example whose bits were derived by
// hand from X.691, round trips at the bounds, and every kind of refusal.

#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "its-station/messages/cam.hpp"
#include "its-station/messages/spatem.hpp"
#include "its-station/messages/tests/bits.hpp"
#include "its-station/messages/tests/samples.hpp"
#include "its-station/messages/tests/signal_samples.hpp"

namespace tb::its::messages {
namespace {

using asn1::Error;
using Bytes = std::vector<std::uint8_t>;
using testing::bits_of;
using testing::from_bits;
using testing::to_bits;
using testing::with_bits;

// clang-format off
// samples::spatem_two_groups(): 35 bytes. Widths from the constraints (X.691 11.5.7.1), an
// extensible SEQUENCE starts with a 0 bit, then one presence bit per OPTIONAL (19.2), a SEQUENCE
// OF with SIZE(lb..ub) sends size - lb (20.6), a fixed-size BIT STRING its bits, bit 0 first
// (16.9), an ENUMERATED without marker its index (14.2).
//  bit width component                      value                          bits
//    0   8  protocolVersion                 2                              00000010
//    8   8  messageID                       spatem (4)                     00000100
//   16  32  stationID                       1001                           00000000000000000000001111101001
//   48   1  SPAT ext                                                       0
//   49   3  timeStamp? name? regional?      absent                         000
//   52   5  intersections (SIZE(1..32))     1                              00000
//   57   1  IntersectionState ext                                          0
//   58   6  name? moy? timeStamp? enabledLanes? maneuverAssistList? regional? 011000
//   64   1  id.region?                      absent                         0
//   65  16  id.id (0..65535)                34                             0000000000100010
//   81   7  revision (0..127)               1                              0000001
//   88  16  status (SIZE(16))               fixedTimeOperation (5)         0000010000000000
//  104  20  moy (0..527040)                 475200                         01110100000001000000
//  124  16  timeStamp (0..65535)            12345                          0011000000111001
//  140   8  states (SIZE(1..255))           2                              00000001
//  148   1  MovementState ext                                              0
//  149   3  movementName? maneuverAssistList? regional?                    000
//  152   8  signalGroup (0..255)            1                              00000001
//  160   4  state-time-speed (SIZE(1..16))  1                              0000
//  164   1  MovementEvent ext                                              0
//  165   3  timing? speeds? regional?       timing                         100
//  168   4  eventState (10 values)          protected-Movement-Allowed (6) 0110
//  172   5  startTime? maxEndTime? likelyTime? confidence? nextTime?       01000
//  177  16  minEndTime (0..36001)           1234                           0000010011010010
//  193  16  maxEndTime                      1300                           0000010100010100
//  209   1  MovementState ext                                              0
//  210   3  movementName? maneuverAssistList? regional?                    000
//  213   8  signalGroup                     2                              00000010
//  221   4  state-time-speed                1                              0000
//  225   1  MovementEvent ext                                              0
//  226   3  timing? speeds? regional?       timing                         100
//  229   4  eventState                      stop-And-Remain (3)            0011
//  233   5  startTime? maxEndTime? likelyTime? confidence? nextTime?       00110
//  238  16  minEndTime                      1264                           0000010011110000
//  254  16  likelyTime                      1270                           0000010011110110
//  270   4  confidence (0..15)              15                             1111
//  274   6  padding                                                        000000
const Bytes kSpatemGolden = {
    0x02, 0x04, 0x00, 0x00, 0x03, 0xE9, 0x00, 0x18, 0x00, 0x11, 0x01, 0x04,
    0x00, 0x74, 0x04, 0x03, 0x03, 0x90, 0x10, 0x01, 0x04, 0x64, 0x02, 0x69,
    0x02, 0x8A, 0x00, 0x10, 0x21, 0x98, 0x13, 0xC0, 0x13, 0xDB, 0xC0,
};
// clang-format on

Bytes must_encode(const Spatem& m) {
  auto bytes = encode(m);
  EXPECT_TRUE(bytes) << asn1::to_string(bytes.error());
  return bytes ? *bytes : Bytes{};
}

std::unique_ptr<Spatem> must_decode(const Bytes& bytes) {
  auto m = std::make_unique<Spatem>();
  auto n = decode(bytes, *m);
  EXPECT_TRUE(n) << asn1::to_string(n.error());
  return m;
}

CodecError decode_error(const Bytes& bytes) {
  auto m = std::make_unique<Spatem>();
  auto n = decode(bytes, *m);
  EXPECT_FALSE(n);
  return n ? CodecError{} : n.error();
}

CodecError encode_error(const Spatem& m) {
  auto bytes = encode(m);
  EXPECT_FALSE(bytes);
  return bytes ? CodecError{} : bytes.error();
}

TEST(Spatem, TwoSignalGroupsEncodeToTheWorkedOutBytes) {
  const auto sample = samples::spatem_two_groups();
  EXPECT_EQ(must_encode(*sample), kSpatemGolden);
  EXPECT_EQ(*must_decode(kSpatemGolden), *sample);
}

TEST(Spatem, EncodesIntoTheCallersBufferAndSaysWhenItIsTooSmall) {
  const auto sample = samples::spatem_two_groups();
  Bytes buf(kSpatemGolden.size());
  auto n = encode(*sample, buf);
  ASSERT_TRUE(n) << asn1::to_string(n.error());
  EXPECT_EQ(*n, kSpatemGolden.size());
  EXPECT_EQ(buf, kSpatemGolden);
  Bytes small(kSpatemGolden.size() - 1);
  auto r = encode(*sample, small);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, Error::kBufferTooSmall);
}

TEST(Spatem, EveryOptionalAtBothEndsOfItsRangeRoundTripsBitForBit) {
  for (bool upper : {false, true}) {
    const auto sample = samples::spatem_at_bounds(upper);
    const Bytes bytes = must_encode(*sample);
    ASSERT_FALSE(bytes.empty());
    const auto back = must_decode(bytes);
    EXPECT_TRUE(*back == *sample) << upper;
    EXPECT_EQ(must_encode(*back), bytes) << upper;
    EXPECT_LE(bytes.size(), kSpatemMaxEncodedSize);
  }
}

TEST(Spatem, TheTypicalMessageRoundTrips) {
  const auto sample = samples::spatem_typical();
  const Bytes bytes = must_encode(*sample);
  EXPECT_EQ(*must_decode(bytes), *sample);
}

TEST(Spatem, EncoderRejectsEveryFieldOutsideItsConstraintNamingIt) {
  struct Case {
    const char* field;
    Error code;
    void (*mutate)(Spatem&);
  };
  const Case cases[] = {
      {"timeStamp", Error::kValueOutOfRange, [](Spatem& m) { m.spat.timeStamp = 527041; }},
      {"name", Error::kSizeOutOfRange, [](Spatem& m) { m.spat.name.emplace(); }},
      {"name", Error::kValueOutOfRange,
       [](Spatem& m) { m.spat.name = char_string<63>("gr\xC3\xBCn"); }},
      {"intersections", Error::kSizeOutOfRange, [](Spatem& m) { m.spat.intersections.clear(); }},
      {"revision", Error::kValueOutOfRange,
       [](Spatem& m) { m.spat.intersections[0].revision = 128; }},
      {"moy", Error::kValueOutOfRange, [](Spatem& m) { m.spat.intersections[0].moy = 527041; }},
      {"enabledLanes", Error::kSizeOutOfRange,
       [](Spatem& m) { m.spat.intersections[0].enabledLanes.emplace(); }},
      {"states", Error::kSizeOutOfRange, [](Spatem& m) { m.spat.intersections[0].states.clear(); }},
      {"maneuverAssistList", Error::kSizeOutOfRange,
       [](Spatem& m) { m.spat.intersections[0].maneuverAssistList.emplace(); }},
      {"movementName", Error::kSizeOutOfRange,
       [](Spatem& m) { m.spat.intersections[0].states[0].movementName.emplace(); }},
      {"state-time-speed", Error::kSizeOutOfRange,
       [](Spatem& m) { m.spat.intersections[0].states[1].state_time_speed.clear(); }},
      {"eventState", Error::kValueOutOfRange,
       [](Spatem& m) {
         m.spat.intersections[0].states[0].state_time_speed[0].eventState =
             static_cast<MovementPhaseState>(10);
       }},
      {"minEndTime", Error::kValueOutOfRange,
       [](Spatem& m) {
         m.spat.intersections[0].states[0].state_time_speed[0].timing->minEndTime = 36002;
       }},
      {"startTime", Error::kValueOutOfRange,
       [](Spatem& m) {
         m.spat.intersections[0].states[0].state_time_speed[0].timing->startTime = 40000;
       }},
      {"maxEndTime", Error::kValueOutOfRange,
       [](Spatem& m) {
         m.spat.intersections[0].states[0].state_time_speed[0].timing->maxEndTime = 65535;
       }},
      {"likelyTime", Error::kValueOutOfRange,
       [](Spatem& m) {
         m.spat.intersections[0].states[1].state_time_speed[0].timing->likelyTime = 36002;
       }},
      {"nextTime", Error::kValueOutOfRange,
       [](Spatem& m) {
         m.spat.intersections[0].states[1].state_time_speed[0].timing->nextTime = 36002;
       }},
      {"confidence", Error::kValueOutOfRange,
       [](Spatem& m) {
         m.spat.intersections[0].states[1].state_time_speed[0].timing->confidence = 16;
       }},
      {"speeds", Error::kSizeOutOfRange,
       [](Spatem& m) { m.spat.intersections[0].states[0].state_time_speed[0].speeds.emplace(); }},
      {"speed", Error::kValueOutOfRange,
       [](Spatem& m) {
         auto& s = m.spat.intersections[0].states[0].state_time_speed[0].speeds.emplace();
         s.emplace_back().speed = 501;
       }},
      {"distance", Error::kValueOutOfRange,
       [](Spatem& m) {
         auto& s = m.spat.intersections[0].states[0].state_time_speed[0].speeds.emplace();
         s.emplace_back().distance = 10001;
       }},
      {"type", Error::kValueOutOfRange,
       [](Spatem& m) {
         auto& s = m.spat.intersections[0].states[0].state_time_speed[0].speeds.emplace();
         s.emplace_back().type = static_cast<AdvisorySpeedType>(4);
       }},
      {"confidence", Error::kValueOutOfRange,
       [](Spatem& m) {
         auto& s = m.spat.intersections[0].states[0].state_time_speed[0].speeds.emplace();
         s.emplace_back().confidence = static_cast<SpeedConfidenceDSRC>(8);
       }},
      {"queueLength", Error::kValueOutOfRange,
       [](Spatem& m) {
         m.spat.intersections[0].maneuverAssistList.emplace().emplace_back().queueLength = 10001;
       }},
      {"availableStorageLength", Error::kValueOutOfRange,
       [](Spatem& m) {
         m.spat.intersections[0]
             .states[0]
             .maneuverAssistList.emplace()
             .emplace_back()
             .availableStorageLength = 10001;
       }},
  };
  for (const Case& c : cases) {
    auto m = samples::spatem_two_groups();
    c.mutate(*m);
    const CodecError e = encode_error(*m);
    EXPECT_EQ(e.code, c.code) << c.field << ": " << asn1::to_string(e);
    EXPECT_STREQ(e.field, c.field) << asn1::to_string(e);
  }
}

TEST(Spatem, EncoderChecksMessageIdAndVersion) {
  auto m = samples::spatem_two_groups();
  m->header.messageID = kMessageIdMapem;
  EXPECT_EQ(encode_error(*m).code, Error::kWrongMessageId);
  m->header.messageID = kMessageIdSpatem;
  m->header.protocolVersion = 1;
  EXPECT_EQ(encode_error(*m).code, Error::kUnsupportedVersion);
}

TEST(Spatem, DecoderRejectsEveryTruncation) {
  for (const Bytes& bytes : {kSpatemGolden, must_encode(*samples::spatem_at_bounds(false)),
                             must_encode(*samples::spatem_typical())}) {
    for (std::size_t n = 0; n < bytes.size(); ++n) {
      const CodecError e = decode_error(Bytes(bytes.begin(), bytes.begin() + n));
      EXPECT_EQ(e.code, Error::kTruncated) << n << ": " << asn1::to_string(e);
    }
  }
}

TEST(Spatem, DecoderNeverMisreadsAMessageCutAtAnyBit) {
  // Cut after every bit, padded with zeros as the encoder pads: shorter in octets, the input
  // ends inside a field; as long, it fails or is a message that encodes to exactly those octets.
  auto m = std::make_unique<Spatem>();
  for (const Bytes& whole : {kSpatemGolden, must_encode(*samples::spatem_at_bounds(false)),
                             must_encode(*samples::spatem_typical())}) {
    const std::string bits = to_bits(whole);
    for (std::size_t n = 0; n < bits.size(); ++n) {
      const Bytes cut = from_bits(bits.substr(0, n));
      auto r = decode(cut, *m);
      if (cut.size() < whole.size()) {
        ASSERT_FALSE(r) << n;
        EXPECT_EQ(r.error().code, Error::kTruncated) << n << ": " << asn1::to_string(r.error());
      } else if (r) {
        EXPECT_EQ(must_encode(*m), cut) << n;
      }
    }
  }
}

TEST(Spatem, DecoderRejectsTrailingOctets) {
  Bytes bytes = kSpatemGolden;
  bytes.push_back(0);
  const CodecError e = decode_error(bytes);
  EXPECT_EQ(e.code, Error::kTrailingData);
  EXPECT_EQ(e.value, 1);
}

TEST(Spatem, DecoderRejectsOtherMessagesAndVersions) {
  auto cam = encode(samples::cam_hf());
  ASSERT_TRUE(cam);
  EXPECT_EQ(decode_error(*cam).code, Error::kWrongMessageId);
  const CodecError mapem = decode_error(with_bits(kSpatemGolden, 8, 8, kMessageIdMapem));
  EXPECT_EQ(mapem.code, Error::kWrongMessageId);
  EXPECT_EQ(mapem.value, kMessageIdMapem);
  for (unsigned v : {0u, 1u, 3u}) {
    const CodecError e = decode_error(with_bits(kSpatemGolden, 0, 8, v));
    EXPECT_EQ(e.code, Error::kUnsupportedVersion) << v;
    EXPECT_EQ(e.value, v);
  }
}

TEST(Spatem, DecoderRejectsValuesOutsideTheirConstraint) {
  struct Case {
    std::size_t bit;
    unsigned width;
    std::uint64_t value;
    Error code;
    const char* field;
  };
  const Case cases[] = {
      {168, 4, 10, Error::kValueOutOfRange, "eventState"},
      {168, 4, 15, Error::kValueOutOfRange, "eventState"},
      {177, 16, 36002, Error::kValueOutOfRange, "minEndTime"},
      {193, 16, 65535, Error::kValueOutOfRange, "maxEndTime"},
      {254, 16, 36002, Error::kValueOutOfRange, "likelyTime"},
      {104, 20, 527041, Error::kValueOutOfRange, "moy"},
      // Sizes inside the module's range but above what is held (dsrc.hpp).
      {52, 5, kIntersectionStatesMax, Error::kSizeOutOfRange, "intersections"},
      {140, 8, kMovementStatesMax, Error::kSizeOutOfRange, "states"},
  };
  for (const Case& c : cases) {
    const CodecError e = decode_error(with_bits(kSpatemGolden, c.bit, c.width, c.value));
    EXPECT_EQ(e.code, c.code) << c.field << ": " << asn1::to_string(e);
    EXPECT_STREQ(e.field, c.field);
    EXPECT_EQ(e.bit_offset, c.bit) << c.field;
  }
}

TEST(Spatem, DecoderRefusesAnAdvisorySpeedTypeOfALaterVersion) {
  auto m = samples::spatem_two_groups();
  m->spat.intersections[0].states[0].state_time_speed[0].speeds.emplace().emplace_back();
  // After the timing of the first event (bit 209): speeds size (4 bits), AdvisorySpeed ext and
  // its five presence bits, then the type's extension bit.
  const std::string bits = to_bits(must_encode(*m));
  ASSERT_EQ(bits.substr(209, 11), "00000000000");
  std::string ext = bits;
  ext.replace(219, 1, "1");
  ext.insert(220, "0000000");  // extension index 0 as a normally small number
  const CodecError e = decode_error(from_bits(ext));
  EXPECT_EQ(e.code, Error::kUnknownExtension);
  EXPECT_STREQ(e.field, "type");
}

TEST(Spatem, DecoderSkipsRegionalExtensionsAndLaterVersionsAdditions) {
  std::string bits = to_bits(kSpatemGolden).substr(0, 274);
  // A regional extension on the first MovementEvent: presence bit, then SIZE(1..4) = 1,
  // regionId addGrpC (3) and an open type (X.691 11.2) of one octet: MovementEvent-addGrpC
  // {stateChangeReason trainPriority}, as Wireshark reads it (tshark_it.cpp).
  bits.replace(167, 1, "1");
  bits.insert(209, "00" + bits_of(3, 8) + bits_of(1, 8) + "01000110");
  // An extension addition of SPAT: the extension bit, then after the root a normally small
  // count (1), its presence bitmap and one open type of one octet (X.691 19.7-19.9).
  bits.replace(48, 1, "1");
  bits += "0" + bits_of(0, 6) + "1" + bits_of(1, 8) + bits_of(0x5A, 8);
  const auto back = must_decode(from_bits(bits));
  EXPECT_EQ(*back, *samples::spatem_two_groups());
  EXPECT_EQ(must_encode(*back), kSpatemGolden);  // what is not held is not sent again
}

TEST(Spatem, DecodingIntoAUsedObjectClearsWhatTheNewMessageLacks) {
  auto m = samples::spatem_at_bounds(true);
  ASSERT_TRUE(decode(kSpatemGolden, *m));
  EXPECT_EQ(*m, *samples::spatem_two_groups());
}

TEST(Spatem, RandomValidMessagesRoundTrip) {
  std::mt19937 rng(34);
  auto pick = [&](std::uint32_t lo, std::uint32_t hi) {
    return std::uniform_int_distribution<std::uint32_t>(lo, hi)(rng);
  };
  auto maybe = [&] { return pick(0, 1) == 1; };
  auto m = std::make_unique<Spatem>();
  for (int round = 0; round < 200; ++round) {
    *m = Spatem{};
    m->header.stationID = pick(0, 0xFFFFFFFF);
    if (maybe())
      m->spat.timeStamp = pick(0, 527040);
    const unsigned n_is = pick(1, 2);
    for (unsigned i = 0; i < n_is; ++i) {
      IntersectionState& is = m->spat.intersections.emplace_back();
      if (maybe())
        is.id.region = static_cast<RoadRegulatorID>(pick(0, 65535));
      is.id.id = static_cast<IntersectionID>(pick(0, 65535));
      is.revision = static_cast<MsgCount>(pick(0, 127));
      is.status = static_cast<IntersectionStatusObject>(pick(0, 65535));
      if (maybe())
        is.moy = pick(0, 527040);
      if (maybe())
        is.timeStamp = static_cast<DSecond>(pick(0, 65535));
      const unsigned n_states = pick(1, 12);
      for (unsigned g = 0; g < n_states; ++g) {
        MovementState& s = is.states.emplace_back();
        s.signalGroup = static_cast<SignalGroupID>(pick(0, 255));
        const unsigned n_ev = pick(1, 3);
        for (unsigned k = 0; k < n_ev; ++k) {
          MovementEvent& e = s.state_time_speed.emplace_back();
          e.eventState = static_cast<MovementPhaseState>(pick(0, 9));
          if (maybe()) {
            TimeChangeDetails& t = e.timing.emplace();
            t.minEndTime = static_cast<TimeMark>(pick(0, 36001));
            if (maybe())
              t.startTime = static_cast<TimeMark>(pick(0, 36001));
            if (maybe())
              t.maxEndTime = static_cast<TimeMark>(pick(0, 36001));
            if (maybe())
              t.likelyTime = static_cast<TimeMark>(pick(0, 36001));
            if (maybe())
              t.confidence = static_cast<TimeIntervalConfidence>(pick(0, 15));
            if (maybe())
              t.nextTime = static_cast<TimeMark>(pick(0, 36001));
          }
          if (maybe()) {
            AdvisorySpeed& a = e.speeds.emplace().emplace_back();
            a.type = static_cast<AdvisorySpeedType>(pick(0, 3));
            if (maybe())
              a.speed = static_cast<SpeedAdvice>(pick(0, 500));
          }
        }
      }
    }
    const Bytes bytes = must_encode(*m);
    const auto back = must_decode(bytes);
    ASSERT_TRUE(*back == *m) << round;
    ASSERT_EQ(must_encode(*back), bytes) << round;
  }
}

// ---- TimeMark: UTC instants in tenths of a second of the hour --------------------------------

// 2026-11-27T11:59:59.950Z: 20 784 days after 1970-01-01, 11 h 59 min 59.95 s.
constexpr std::int64_t kBeforeNoon = (20784LL * 86400 + 11 * 3600 + 59 * 60 + 59) * 1000 + 950;

TEST(TimeMark, CountsTenthsOfASecondSinceTheStartOfTheUtcHour) {
  EXPECT_EQ(time_mark_from_utc_ms(kBeforeNoon), 35999);   // 59 min 59.9 s, rounded down
  EXPECT_EQ(time_mark_from_utc_ms(kBeforeNoon + 50), 0);  // noon
  EXPECT_EQ(time_mark_from_utc_ms(kBeforeNoon + 50 + 123'456), 1234);
  EXPECT_EQ(time_mark_from_utc_ms(0), 0);  // the Unix epoch is the start of an hour
}

TEST(TimeMark, AReceiverTakesTheInstantNearestToItsOwnClock) {
  const std::int64_t noon = kBeforeNoon + 50;
  // Just after the hour, a mark from the end of the hour before is in the past...
  EXPECT_EQ(utc_ms_from_time_mark(35999, noon + 200), noon - 100);
  // ...and just before it, a mark from the start of the next hour is in the future.
  EXPECT_EQ(utc_ms_from_time_mark(20, kBeforeNoon), noon + 2000);
  // Within the hour, the hour of now.
  EXPECT_EQ(utc_ms_from_time_mark(1234, noon + 60'000), noon + 123'400);
  for (std::int64_t now = noon - 1'800'000; now < noon + 1'800'000; now += 7'777) {
    const std::int64_t at = now + 25'000;  // a change 25 s ahead
    EXPECT_EQ(utc_ms_from_time_mark(time_mark_from_utc_ms(at), now), at - at % 100) << now;
  }
}

}  // namespace
}  // namespace tb::its::messages
