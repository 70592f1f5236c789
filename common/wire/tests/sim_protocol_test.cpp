#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>

#include "common/util/bytes.hpp"
#include "common/wire/sim_protocol.hpp"

namespace tb::wire::sim {
namespace {

using Bytes = std::vector<std::uint8_t>;

/// Feeds @p bytes in slices of @p chunk and collects every complete frame.
struct Feed {
  std::vector<Frame> frames;
  std::optional<ProtocolError> error;
};
Feed feed(FrameParser& p, const Bytes& bytes, std::size_t chunk) {
  Feed out;
  for (std::size_t at = 0; at < bytes.size() && !out.error; at += chunk) {
    std::span<const std::uint8_t> data(bytes.data() + at, std::min(chunk, bytes.size() - at));
    while (!data.empty()) {
      auto r = p.parse(data);
      if (!r) {
        out.error = r.error();
        break;
      }
      if (*r == FrameParser::Status::kFrame)
        out.frames.push_back(p.frame());
    }
  }
  return out;
}

ClientMessage client_roundtrip(const ClientMessage& m) {
  FrameParser p(Sender::kClient);
  auto f = feed(p, encode(m), 1000);
  EXPECT_FALSE(f.error);
  EXPECT_EQ(f.frames.size(), 1u);
  auto d = decode_client(f.frames.at(0));
  EXPECT_TRUE(d) << to_string(d.error());
  return *d;
}

ServerMessage server_roundtrip(const ServerMessage& m) {
  FrameParser p(Sender::kServer);
  auto f = feed(p, encode(m), 1 << 20);
  EXPECT_FALSE(f.error);
  EXPECT_EQ(f.frames.size(), 1u);
  auto d = decode_server(f.frames.at(0));
  EXPECT_TRUE(d) << to_string(d.error());
  return *d;
}

VehicleState state(std::uint32_t station, std::uint64_t tick) {
  VehicleState s;
  s.station_id = station;
  s.tick = tick;
  s.sim_time_ns = static_cast<std::int64_t>(tick) * 10'000'000;
  s.position = {1.5 * station, -2.0, 0.3};
  s.yaw = 0.25f;
  s.speed = 12.5f;
  s.controls = {0.5f, 0.0f, -0.25f, false, false};
  s.gear = 3;
  s.lights = kLowBeam;
  return s;
}

Welcome sample_welcome() {
  Welcome w;
  w.server_name = "sim-server test";
  w.step_ns = 10'000'000;
  w.world_start_ns = 1'748'854'800'000'000'000;  // 2025-06-02T09:00:00Z
  VehicleInfo a;
  a.index = 0;
  a.id = "ego";
  a.station_id = 1001;
  a.color = "#d02020";
  a.length_m = 4.255f;
  a.width_m = 1.799f;
  a.height_m = 1.452f;
  a.wheelbase_m = 2.637f;
  a.track_m = 1.54f;
  a.wheel_radius_m = 0.316f;
  a.max_steer_rad = 0.628f;
  a.driver = "alice";
  VehicleInfo b = a;
  b.index = 1;
  b.id = "other";
  b.station_id = 1002;
  b.driver_kind = DriverKind::kLaneFollow;
  b.driver = "";
  w.vehicles = {a, b};
  w.scenario_json = R"({"name":"x","map":{"type":"opendrive","file":"maps/x.xodr"}})";
  w.map_text = "<OpenDRIVE><header revMajor=\"1\" revMinor=\"7\"/></OpenDRIVE>\n";
  return w;
}

/// Junction 100's four groups and junction 7's one, as a fixed-time plan sends them.
SignalStates sample_signals() {
  const std::int64_t t = 1'795'000'000'000;  // 2026-11-19T09:46:40Z
  return SignalStates{t,
                      {{7, 254, MovementPhaseState::kDark, 0, 0},
                       {100, 1, MovementPhaseState::kProtectedClearance, t + 2000, t + 2000},
                       {100, 2, MovementPhaseState::kStopAndRemain, t + 5000, t + 5000},
                       {100, 3, MovementPhaseState::kProtectedMovementAllowed, t + 1, t + 1},
                       {100, 4, MovementPhaseState::kPreMovement, t + 1000, t + 900}}};
}

TEST(SimProtocol, ClientMessagesRoundTrip) {
  const std::vector<ClientMessage> msgs = {
      Hello{"sim-client alice"},
      Attach{Role::kDriver, 7},
      Attach{Role::kWatcher, 0},
      ControlsMsg{3, Controls{0.75f, 0.1f, -0.5f, true, true}, kIndicatorLeft | kLowBeam},
      ControlsMsg{3, Controls{0.75f, 0.1f, -0.5f, true, true}, kLowBeam, 1'795'312'926'004'965'889},
      ControlsMsg{0, {}, 0, -1},  // the input time is only traced: any value decodes
      Detach{3},
      ControlsBatch{{ControlsMsg{0, Controls{0.5f, 0.0f, 0.25f, false, false}, kLowBeam, 11},
                     ControlsMsg{4095, Controls{0.0f, 1.0f, -1.0f, true, true}, 0, -7}}},
  };
  for (const auto& m : msgs)
    EXPECT_EQ(client_roundtrip(m), m);
}

TEST(SimProtocol, ControlsLayout) {
  // PROTOCOL.md: u16 vehicle, f32 throttle, brake, steer, u8 flags, u16 lights, i64 input_ns.
  const auto b = encode(
      ControlsMsg{0x0102, Controls{1.0f, 0.0f, 0.0f, true, false}, 0x0304, 0x1122334455667788});
  ASSERT_EQ(b.size(), kHeaderSize + 25);
  EXPECT_EQ(b[2], 7);          // version
  EXPECT_EQ(b[4], 25);         // payload length
  EXPECT_EQ(b[8], 0x02);       // vehicle, little-endian
  EXPECT_EQ(b[8 + 14], 0x01);  // flags: reverse
  EXPECT_EQ(b[8 + 15], 0x04);  // lights
  EXPECT_EQ(b[8 + 17], 0x88);  // input_ns, little-endian
  EXPECT_EQ(b[8 + 24], 0x11);
}

TEST(SimProtocol, ServerMessagesRoundTrip) {
  StateFrame s;
  s.tick = 42;
  s.sim_time_ns = 420'000'000;
  s.step_wall_ns = 1'732'233'600'000'000'000;
  s.vehicles = {state(1001, 42), state(1002, 42), state(1003, 42)};
  const std::vector<ServerMessage> msgs = {
      sample_welcome(),
      AttachResult{Role::kDriver, 1, AttachStatus::kAlreadyDriven, "driven by 'bob'"},
      s,
      DriverChanged{1, "carol"},
      Closing{CloseReason::kTooSlow, "send queue full"},
      Closing{CloseReason::kScenarioFinished, "scenario finished"},
      sample_signals(),
      SignalStates{1'795'000'000'000, {}},
  };
  for (const auto& m : msgs)
    EXPECT_EQ(server_roundtrip(m), m);
}

TEST(SimProtocol, StateFramesOfTheWarmUpHaveNegativeSimTime) {
  const std::vector<VehicleState> v = {state(1, 5)};
  FrameParser p(Sender::kServer);
  auto warm = feed(p, encode_state(5, -2'950'000'000, 77, v, 99), 1 << 20);
  ASSERT_EQ(warm.frames.size(), 1u);
  auto d = decode_server(warm.frames[0]);
  ASSERT_TRUE(d);
  EXPECT_EQ(std::get<StateFrame>(*d).sim_time_ns, -2'950'000'000);
  FrameParser q(Sender::kServer);
  auto early = feed(q, encode_state(5, kMinSimTimeNs - 1, 77, v, 99), 1 << 20);
  ASSERT_EQ(early.frames.size(), 1u);
  EXPECT_EQ(decode_server(early.frames[0]).error(), ProtocolError::kBadValue);
}

TEST(SimProtocol, EncodeStateStampsSendTimeIntoEveryRecord) {
  const std::vector<VehicleState> v = {state(1, 5), state(2, 5)};
  const auto bytes = encode_state(5, 50'000'000, 77, v, 99);
  FrameParser p(Sender::kServer);
  auto f = feed(p, bytes, bytes.size());
  ASSERT_EQ(f.frames.size(), 1u);
  auto d = decode_server(f.frames[0]);
  ASSERT_TRUE(d);
  const auto& s = std::get<StateFrame>(*d);
  EXPECT_EQ(s.tick, 5u);
  EXPECT_EQ(s.step_wall_ns, 77);
  ASSERT_EQ(s.vehicles.size(), 2u);
  EXPECT_EQ(s.vehicles[1].station_id, 2u);
  EXPECT_EQ(s.vehicles[0].send_wall_ns, 99);
  EXPECT_EQ(s.vehicles[1].send_wall_ns, 99);
}

TEST(SimProtocol, ParsesFramesFedOneByteAtATime) {
  Bytes stream;
  for (const ClientMessage& m : std::vector<ClientMessage>{
           Hello{"a"}, Attach{Role::kDriver, 0}, ControlsMsg{0, {1.0f, 0, 0, false, false}, 0}}) {
    auto b = encode(m);
    stream.insert(stream.end(), b.begin(), b.end());
  }
  for (std::size_t chunk : {std::size_t{1}, std::size_t{3}, std::size_t{7}, stream.size()}) {
    FrameParser p(Sender::kClient);
    auto f = feed(p, stream, chunk);
    ASSERT_FALSE(f.error) << "chunk " << chunk;
    ASSERT_EQ(f.frames.size(), 3u) << "chunk " << chunk;
    EXPECT_EQ(f.frames[0].type, MessageType::kHello);
    EXPECT_EQ(f.frames[1].type, MessageType::kAttach);
    EXPECT_EQ(f.frames[2].type, MessageType::kControls);
    auto c = decode_client(f.frames[2]);
    ASSERT_TRUE(c);
    EXPECT_EQ(std::get<ControlsMsg>(*c).controls.throttle, 1.0f);
  }
}

TEST(SimProtocol, PartialHeaderNeedsMore) {
  const auto b = encode(Hello{"abc"});
  FrameParser p(Sender::kClient);
  std::span<const std::uint8_t> part(b.data(), 5);
  auto r = p.parse(part);
  ASSERT_TRUE(r);
  EXPECT_EQ(*r, FrameParser::Status::kNeedMore);
  EXPECT_TRUE(part.empty());
}

Bytes header(std::uint8_t type, std::uint32_t size, std::uint8_t version = kProtocolVersion) {
  Bytes b(kHeaderSize);
  ByteWriter w(b);
  w.le<std::uint8_t>('S');
  w.le<std::uint8_t>('P');
  w.le(version);
  w.le(type);
  w.le(size);
  return b;
}

TEST(SimProtocol, ClosingReasonsOutsideTheKnownOnesAreBadValues) {
  // Reason 4 (scenario finished, version 5) is the last known one: 0 and 5 are malformed.
  for (const std::uint8_t reason : {0, 1, 4, 5, 255}) {
    SCOPED_TRACE(static_cast<int>(reason));
    Bytes b = header(0x85, 2);
    b.push_back(reason);
    b.push_back(0);  // empty text
    FrameParser p(Sender::kServer);
    auto f = feed(p, b, b.size());
    ASSERT_EQ(f.frames.size(), 1u);
    const auto d = decode_server(f.frames[0]);
    if (reason == 1 || reason == 4) {
      ASSERT_TRUE(d);
      EXPECT_EQ(static_cast<int>(std::get<Closing>(*d).reason), reason);
    } else {
      ASSERT_FALSE(d);
      EXPECT_EQ(d.error(), ProtocolError::kBadValue);
    }
  }
  EXPECT_EQ(to_string(CloseReason::kScenarioFinished), "scenario finished");
}

TEST(SimProtocol, FuzzSeedsAreOfTheCurrentVersion) {
  // The seed corpus (tests/fuzz/sim_protocol; first byte: sender, second: where the stream is
  // cut) must hold whole frames that decode, or the fuzzer starts from rejected headers only.
  // Rewrite the seeds whenever kProtocolVersion changes.
  for (const auto& [file, from] : {std::pair{"client_session", Sender::kClient},
                                   std::pair{"server_messages", Sender::kServer}}) {
    SCOPED_TRACE(file);
    std::ifstream in(std::string("tests/fuzz/sim_protocol/") + file, std::ios::binary);
    ASSERT_TRUE(in) << "run from the source root";
    const Bytes seed((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_GT(seed.size(), 2u);
    FrameParser p(from);
    auto f = feed(p, Bytes(seed.begin() + 2, seed.end()), seed.size());
    EXPECT_FALSE(f.error);
    ASSERT_GE(f.frames.size(), 3u);
    for (const auto& fr : f.frames) {
      if (from == Sender::kClient)
        EXPECT_TRUE(decode_client(fr)) << to_string(fr.type);
      else
        EXPECT_TRUE(decode_server(fr)) << to_string(fr.type);
    }
  }
}

TEST(SimProtocol, RejectsOversizedBeforeBufferingThePayload) {
  FrameParser p(Sender::kClient);
  // A client claiming a 1 GiB Hello is refused on its header alone.
  auto f = feed(p, header(0x01, 1u << 30), 64);
  ASSERT_TRUE(f.error);
  EXPECT_EQ(*f.error, ProtocolError::kOversized);
  // Controls have a fixed size; one byte more is oversized too.
  FrameParser q(Sender::kClient);
  f = feed(q, header(0x03, 26), 64);
  ASSERT_TRUE(f.error);
  EXPECT_EQ(*f.error, ProtocolError::kOversized);
}

TEST(SimProtocol, RejectsUnknownTypeBadMagicAndVersion) {
  FrameParser a(Sender::kClient);
  EXPECT_EQ(*feed(a, header(0x42, 0), 64).error, ProtocolError::kUnknownType);
  // A server message type coming from a client is just as unknown.
  FrameParser b(Sender::kClient);
  EXPECT_EQ(*feed(b, header(0x83, 0), 64).error, ProtocolError::kUnknownType);
  FrameParser c(Sender::kServer);
  EXPECT_EQ(*feed(c, header(0x03, 17), 64).error, ProtocolError::kUnknownType);
  FrameParser d(Sender::kClient);
  EXPECT_EQ(*feed(d, Bytes{'G', 'E', 'T', ' ', '/', ' ', 'H', 'T'}, 64).error,
            ProtocolError::kBadMagic);
  FrameParser e(Sender::kClient);
  EXPECT_EQ(*feed(e, header(0x01, 1, 8), 64).error, ProtocolError::kUnsupportedVersion);
  // Version 6 (no SignalStates) is refused: a version-6 client would close on the lights.
  FrameParser e6(Sender::kServer);
  EXPECT_EQ(*feed(e6, header(0x83, 26, 6), 64).error, ProtocolError::kUnsupportedVersion);
  FrameParser c6(Sender::kClient);
  EXPECT_EQ(*feed(c6, header(0x01, 1, 6), 64).error, ProtocolError::kUnsupportedVersion);
  // SignalStates only come from the server.
  FrameParser s86(Sender::kClient);
  EXPECT_EQ(*feed(s86, header(0x86, 10), 64).error, ProtocolError::kUnknownType);
  // Version 5 (no ControlsBatch) is refused: a version-5 server would close on the batch.
  FrameParser e5(Sender::kClient);
  EXPECT_EQ(*feed(e5, header(0x01, 1, 5), 64).error, ProtocolError::kUnsupportedVersion);
  // A batch coming from the server is a type it may not send.
  FrameParser s5(Sender::kServer);
  EXPECT_EQ(*feed(s5, header(0x05, 27), 64).error, ProtocolError::kUnknownType);
  // Version 4 (no "scenario finished" reason) is refused too.
  FrameParser e4(Sender::kServer);
  EXPECT_EQ(*feed(e4, header(0x85, 2, 4), 64).error, ProtocolError::kUnsupportedVersion);
  // Version 1 (Controls without the input time) is refused, not misread.
  FrameParser g(Sender::kClient);
  EXPECT_EQ(*feed(g, header(0x03, 17, 1), 64).error, ProtocolError::kUnsupportedVersion);
  // Version 2 (a Welcome without the map) likewise, and 3 (without the world's start time).
  FrameParser h(Sender::kServer);
  EXPECT_EQ(*feed(h, header(0x81, 100, 2), 64).error, ProtocolError::kUnsupportedVersion);
  FrameParser i(Sender::kServer);
  EXPECT_EQ(*feed(i, header(0x81, 100, 3), 64).error, ProtocolError::kUnsupportedVersion);
}

TEST(SimProtocol, StaysFailedAfterAnError) {
  FrameParser p(Sender::kClient);
  ASSERT_TRUE(feed(p, header(0x42, 0), 64).error);
  const auto good = encode(Hello{"x"});
  auto f = feed(p, good, good.size());
  ASSERT_TRUE(f.error);
  EXPECT_EQ(*f.error, ProtocolError::kParserFailed);
}

Frame frame(MessageType t, Bytes payload) {
  return Frame{t, std::move(payload)};
}

TEST(SimProtocol, RejectsMalformedPayloads) {
  // Controls one byte short.
  auto c = encode(ControlsMsg{});
  Bytes payload(c.begin() + kHeaderSize, c.end() - 1);
  EXPECT_EQ(decode_client(frame(MessageType::kControls, payload)).error(),
            ProtocolError::kBadLength);
  // NaN throttle.
  ControlsMsg nan;
  nan.controls.throttle = std::numeric_limits<float>::quiet_NaN();
  c = encode(nan);
  EXPECT_EQ(
      decode_client(frame(MessageType::kControls, Bytes(c.begin() + kHeaderSize, c.end()))).error(),
      ProtocolError::kNotFinite);
  // Unknown flag bits.
  c = encode(ControlsMsg{});
  Bytes flags(c.begin() + kHeaderSize, c.end());
  flags[14] = 0x80;
  EXPECT_EQ(decode_client(frame(MessageType::kControls, flags)).error(), ProtocolError::kBadValue);
  // Role 9.
  EXPECT_EQ(decode_client(frame(MessageType::kAttach, Bytes{9, 0, 0})).error(),
            ProtocolError::kBadValue);
  // A name with a control character, and one whose length runs past the payload.
  EXPECT_EQ(decode_client(frame(MessageType::kHello, Bytes{2, 'a', '\n'})).error(),
            ProtocolError::kBadText);
  EXPECT_EQ(decode_client(frame(MessageType::kHello, Bytes{5, 'a'})).error(),
            ProtocolError::kBadLength);
  // Trailing bytes after the name.
  EXPECT_EQ(decode_client(frame(MessageType::kHello, Bytes{1, 'a', 'b'})).error(),
            ProtocolError::kBadLength);
}

TEST(SimProtocol, ControlsBatchLayout) {
  // PROTOCOL.md: u16 count, then count Controls payloads.
  ControlsBatch m;
  for (std::uint16_t v = 0; v < 3; ++v)
    m.entries.push_back(ControlsMsg{static_cast<std::uint16_t>(0x0100 + v),
                                    Controls{1.0f, 0.0f, 0.0f, false, true}, 0x0304,
                                    0x1122334455667788});
  const auto b = encode(m);
  ASSERT_EQ(b.size(), kHeaderSize + 2 + 3 * 25);
  EXPECT_EQ(b[3], 0x05);  // type
  EXPECT_EQ(b[4], 2 + 3 * 25);
  EXPECT_EQ(b[8], 3);  // count, little-endian
  EXPECT_EQ(b[9], 0);
  for (std::size_t i = 0; i < 3; ++i) {
    const std::size_t at = kHeaderSize + 2 + i * 25;
    EXPECT_EQ(b[at], i);  // vehicle, little-endian
    EXPECT_EQ(b[at + 1], 0x01);
    EXPECT_EQ(b[at + 14], 0x02);  // flags: handbrake
    EXPECT_EQ(b[at + 24], 0x11);  // last byte of input_ns
  }
}

TEST(SimProtocol, ControlsBatchOfEveryVehicleFitsItsBound) {
  ControlsBatch m;
  for (std::size_t v = 0; v < kMaxVehicles; ++v)
    m.entries.push_back(ControlsMsg{static_cast<std::uint16_t>(v), {}, 0, 1});
  const auto b = encode(m);
  EXPECT_EQ(b.size(), kHeaderSize + kMaxControlsBatchPayload);
  EXPECT_EQ(client_roundtrip(m), ClientMessage{m});
  // The encoder keeps to the limit rather than writing a frame the server refuses.
  m.entries.push_back(ControlsMsg{});
  EXPECT_EQ(encode(m).size(), kHeaderSize + kMaxControlsBatchPayload);
  // A header announcing one byte more than the bound is refused before any payload.
  Bytes h = encode(ControlsBatch{{ControlsMsg{}}});
  h.resize(kHeaderSize);
  const auto big = static_cast<std::uint32_t>(kMaxControlsBatchPayload + 1);
  std::memcpy(h.data() + 4, &big, 4);
  FrameParser p(Sender::kClient);
  const auto f = feed(p, h, 64);
  ASSERT_TRUE(f.error);
  EXPECT_EQ(*f.error, ProtocolError::kOversized);
}

TEST(SimProtocol, RejectsMalformedControlsBatches) {
  const auto payload = [](const ControlsBatch& m) {
    const auto b = encode(m);
    return Bytes(b.begin() + kHeaderSize, b.end());
  };
  const ControlsBatch two{{ControlsMsg{0, {}, 0, 1}, ControlsMsg{1, {}, 0, 2}}};
  const Bytes good = payload(two);
  ASSERT_TRUE(decode_client(frame(MessageType::kControlsBatch, good)));
  // Every length but the right one: a count that does not match the entries, a cut entry,
  // a trailing byte, no count at all.
  for (std::size_t n = 0; n < good.size(); ++n) {
    EXPECT_EQ(
        decode_client(frame(MessageType::kControlsBatch, Bytes(good.begin(), good.begin() + n)))
            .error(),
        ProtocolError::kBadLength)
        << n << " bytes";
  }
  Bytes longer = good;
  longer.push_back(0);
  EXPECT_EQ(decode_client(frame(MessageType::kControlsBatch, longer)).error(),
            ProtocolError::kBadLength);
  Bytes miscount = good;
  miscount[0] = 3;
  EXPECT_EQ(decode_client(frame(MessageType::kControlsBatch, miscount)).error(),
            ProtocolError::kBadLength);
  // An empty batch says nothing: malformed.
  EXPECT_EQ(decode_client(frame(MessageType::kControlsBatch, Bytes{0, 0})).error(),
            ProtocolError::kBadValue);
  // One bad entry spoils the batch: a NaN in the second, unknown flags in the first.
  ControlsBatch nan = two;
  nan.entries[1].controls.steer = std::numeric_limits<float>::infinity();
  EXPECT_EQ(decode_client(frame(MessageType::kControlsBatch, payload(nan))).error(),
            ProtocolError::kNotFinite);
  Bytes flags = good;
  flags[2 + 14] = 0x04;
  EXPECT_EQ(decode_client(frame(MessageType::kControlsBatch, flags)).error(),
            ProtocolError::kBadValue);
  // More entries than the protocol has vehicles, with a payload that matches the count.
  const std::size_t over = kMaxVehicles + 1;
  Bytes too_many(2 + over * kControlsEntrySize, 0);
  too_many[0] = static_cast<std::uint8_t>(over & 0xff);
  too_many[1] = static_cast<std::uint8_t>(over >> 8);
  EXPECT_EQ(decode_client(frame(MessageType::kControlsBatch, too_many)).error(),
            ProtocolError::kOversized);
}

TEST(SimProtocol, RejectsStateWithWrongCountOrBadRecord) {
  const std::vector<VehicleState> v = {state(1, 1), state(2, 1)};
  auto b = encode_state(1, 10'000'000, 0, v, 0);
  Bytes payload(b.begin() + kHeaderSize, b.end());
  // Claims three records but carries two.
  payload[24] = 3;
  EXPECT_EQ(decode_server(frame(MessageType::kState, payload)).error(), ProtocolError::kBadLength);
  payload[24] = 2;
  // Second record's magic broken.
  payload[26 + kVehicleStateSize] = 'X';
  EXPECT_EQ(decode_server(frame(MessageType::kState, payload)).error(), ProtocolError::kBadState);
}

TEST(SimProtocol, WelcomeRejectsTruncationAtEveryLength) {
  auto b = encode(sample_welcome());
  Bytes payload(b.begin() + kHeaderSize, b.end());
  for (std::size_t n = 0; n < payload.size(); ++n) {
    auto d =
        decode_server(frame(MessageType::kWelcome, Bytes(payload.begin(), payload.begin() + n)));
    EXPECT_FALSE(d) << "accepted a Welcome cut at " << n;
  }
}

TEST(SimProtocol, WelcomeEndsWithTheScenarioAndTheMapText) {
  // PROTOCOL.md, version 3: ... u32 json_length, JSON, u32 map_length, map.
  const Welcome w = sample_welcome();
  const auto b = encode(w);
  const std::size_t map = w.map_text.size(), json = w.scenario_json.size();
  ASSERT_GT(b.size(), kHeaderSize + 8 + map + json);
  EXPECT_EQ(std::string(b.end() - static_cast<long>(map), b.end()), w.map_text);
  const auto at = b.end() - static_cast<long>(map) - 4;
  EXPECT_EQ(at[0] | at[1] << 8 | at[2] << 16 | at[3] << 24, static_cast<int>(map));
  EXPECT_EQ(std::string(at - static_cast<long>(json), at), w.scenario_json);
  // A built-in layout: no map text, four zero bytes.
  Welcome builtin = w;
  builtin.map_text.clear();
  EXPECT_EQ(server_roundtrip(builtin), ServerMessage{builtin});
}

TEST(SimProtocol, WelcomeAndStateHaveTheirOwnBounds) {
  // A Welcome may carry a map of up to 32 MiB; a State frame stays within 4 MiB.
  FrameParser p(Sender::kServer);
  auto f = feed(p, header(0x81, static_cast<std::uint32_t>(kMaxWelcomePayload + 1)), 64);
  ASSERT_TRUE(f.error);
  EXPECT_EQ(*f.error, ProtocolError::kOversized);
  FrameParser q(Sender::kServer);
  f = feed(q, header(0x81, static_cast<std::uint32_t>(kMaxWelcomePayload)), 64);
  EXPECT_FALSE(f.error);
  FrameParser r(Sender::kServer);
  f = feed(r, header(0x83, static_cast<std::uint32_t>(kMaxServerPayload + 1)), 64);
  ASSERT_TRUE(f.error);
  EXPECT_EQ(*f.error, ProtocolError::kOversized);
  EXPECT_GE(kMaxWelcomePayload, kMaxMapText + kMaxScenarioText);
}

TEST(SimProtocol, ClampCountsOutOfRangeValues) {
  Controls c{1.5f, -0.2f, -3.0f, false, false};
  EXPECT_EQ(clamp(c), 3);
  EXPECT_EQ(c.throttle, 1.0f);
  EXPECT_EQ(c.brake, 0.0f);
  EXPECT_EQ(c.steer, -1.0f);
  Controls ok{0.3f, 0.0f, 1.0f, false, false};
  EXPECT_EQ(clamp(ok), 0);
  EXPECT_EQ(ok.steer, 1.0f);
}

TEST(SimProtocol, ConversationRequiresHelloFirstAndAttachBeforeControls) {
  Conversation c;
  const ClientMessage controls = ControlsMsg{0, {}, 0};
  EXPECT_EQ(c.check(Attach{Role::kDriver, 0}).error(), ProtocolError::kOutOfOrder);
  EXPECT_EQ(c.check(controls).error(), ProtocolError::kOutOfOrder);
  ASSERT_TRUE(c.check(Hello{"a"}));
  c.on_hello();
  EXPECT_EQ(c.check(Hello{"again"}).error(), ProtocolError::kOutOfOrder);
  // Controls before attach.
  EXPECT_EQ(c.check(controls).error(), ProtocolError::kOutOfOrder);
  EXPECT_TRUE(c.check(Attach{Role::kDriver, 0}));
  c.on_driving(0);
  EXPECT_TRUE(c.check(controls));
  // Controls for a vehicle driven by someone else.
  EXPECT_EQ(c.check(ControlsMsg{1, {}, 0}).error(), ProtocolError::kOutOfOrder);
  EXPECT_TRUE(c.check(Detach{0}));
  c.on_released(0);
  EXPECT_EQ(c.check(controls).error(), ProtocolError::kOutOfOrder);
}

ControlsMsg entry(std::uint16_t vehicle) {
  return ControlsMsg{vehicle, {}, 0, 0};
}

TEST(SimProtocol, ConversationRefusesABatchWithAnyVehicleNotDriven) {
  Conversation c;
  c.on_hello();
  for (std::uint16_t v : {2, 3, 4000})
    c.on_driving(v);
  c.on_driving(3);  // twice: still driven once
  EXPECT_EQ(c.driven(), (std::vector<std::uint16_t>{2, 3, 4000}));
  EXPECT_TRUE(c.check(ControlsBatch{{entry(2), entry(4000), entry(3)}}));
  // One vehicle the connection does not drive refuses the whole batch, wherever it is.
  EXPECT_EQ(c.check(ControlsBatch{{entry(2), entry(5)}}).error(), ProtocolError::kOutOfOrder);
  EXPECT_EQ(c.check(ControlsBatch{{entry(65535), entry(2)}}).error(), ProtocolError::kOutOfOrder);
  c.on_released(3);
  c.on_released(7);  // never driven: nothing changes
  EXPECT_FALSE(c.drives(3));
  EXPECT_TRUE(c.drives(4000));
  EXPECT_EQ(c.check(ControlsBatch{{entry(2), entry(3)}}).error(), ProtocolError::kOutOfOrder);
  EXPECT_EQ(c.driven(), (std::vector<std::uint16_t>{2, 4000}));
}

TEST(SimProtocol, SignalStatesLayout) {
  // PROTOCOL.md: i64 world_time_ms, u16 count, count × (u16 intersection, u8 signal group,
  // u8 MovementPhaseState, i64 next_change_ms, i64 likely_change_ms), little-endian.
  const SignalStates m{0x0102030405060708,
                       {{0x1234, 9, MovementPhaseState::kProtectedClearance, 0x1122, 0x3344}}};
  const auto b = encode(m);
  ASSERT_EQ(b.size(), kHeaderSize + 10 + 20);
  EXPECT_EQ(b[2], 7);
  EXPECT_EQ(b[3], 0x86);
  EXPECT_EQ(b[4], 30);
  EXPECT_EQ(b[8], 0x08);  // world time, least significant byte first
  EXPECT_EQ(b[15], 0x01);
  EXPECT_EQ(b[16], 1);  // count
  EXPECT_EQ(b[18], 0x34);
  EXPECT_EQ(b[19], 0x12);
  EXPECT_EQ(b[20], 9);
  EXPECT_EQ(b[21], 8);  // protected-clearance (amber)
  EXPECT_EQ(b[22], 0x22);
  EXPECT_EQ(b[30], 0x44);
}

TEST(SimProtocol, RejectsMalformedSignalStates) {
  const auto good = encode(sample_signals());
  const Bytes payload(good.begin() + kHeaderSize, good.end());
  ASSERT_TRUE(decode_server(frame(MessageType::kSignalStates, payload)));
  // Cut anywhere: never accepted, never read past the end.
  for (std::size_t n = 0; n < payload.size(); ++n) {
    EXPECT_FALSE(decode_server(
        frame(MessageType::kSignalStates, Bytes(payload.begin(), payload.begin() + n))))
        << "accepted SignalStates cut at " << n;
  }
  auto with = [&](std::size_t at, std::uint8_t v) {
    Bytes p = payload;
    p[at] = v;
    return decode_server(frame(MessageType::kSignalStates, p));
  };
  const std::size_t e1 = 10 + 20;                            // second entry: (100, 1)
  EXPECT_EQ(with(8, 4).error(), ProtocolError::kBadLength);  // claims 4 entries, carries 5
  EXPECT_EQ(with(8, 6).error(), ProtocolError::kBadLength);
  EXPECT_EQ(with(e1 + 3, 10).error(), ProtocolError::kBadValue);     // no MovementPhaseState 10
  EXPECT_EQ(with(e1 + 2, 0).error(), ProtocolError::kBadValue);      // SignalGroupID 0 reserved
  EXPECT_EQ(with(10 + 2, 255).error(), ProtocolError::kBadValue);    // and 255
  EXPECT_EQ(with(e1 + 2, 2).error(), ProtocolError::kBadValue);      // (100, 2) twice
  EXPECT_EQ(with(e1 + 0, 6).error(), ProtocolError::kBadValue);      // (6, 1) after (7, 254)
  EXPECT_EQ(with(e1 + 11, 0x80).error(), ProtocolError::kBadValue);  // next change < 0
  EXPECT_EQ(with(e1 + 19, 0x80).error(), ProtocolError::kBadValue);  // likely time < 0
  EXPECT_EQ(with(7, 0x80).error(), ProtocolError::kBadValue);        // world time < 0
  // Bounded: more groups than a frame may hold are refused on the header alone.
  FrameParser p(Sender::kServer);
  const auto over = static_cast<std::uint32_t>(10 + (kMaxSignalGroupStates + 1) * 20);
  EXPECT_EQ(*feed(p, header(0x86, over), 64).error, ProtocolError::kOversized);
  EXPECT_EQ(to_string(MovementPhaseState::kStopAndRemain), "stop-And-Remain");
  EXPECT_EQ(to_string(MovementPhaseState::kProtectedMovementAllowed), "protected-Movement-Allowed");
  EXPECT_EQ(to_string(MovementPhaseState::kPreMovement), "pre-Movement");
  EXPECT_EQ(to_string(MovementPhaseState::kProtectedClearance), "protected-clearance");
}

TEST(SimProtocol, ErrorsHaveNames) {
  for (int e = 1; e <= static_cast<int>(ProtocolError::kParserFailed); ++e)
    EXPECT_NE(to_string(static_cast<ProtocolError>(e)), "unknown error");
}

}  // namespace
}  // namespace tb::wire::sim
