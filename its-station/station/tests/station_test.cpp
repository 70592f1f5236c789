// A Station built from fake ports — a hand-fed receiver, the test link, the manual clock and a
// recording MQTT sink — as station-host builds hundreds: no sockets, no sleeps. What it sends is
// decoded off the link and graded against the world the test sets up (positions, speeds, the
// vehicle's size), not against figures the stack printed.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <unistd.h>
#include <nlohmann/json.hpp>

#include "common/clock/gnss_disciplined_runtime.hpp"
#include "common/clock/runtime.hpp"
#include "common/geodesy/local_frame.hpp"
#include "common/mqtt/sink.hpp"
#include "common/trace/tracer.hpp"
#include "its-station/btp/header.hpp"
#include "its-station/geonet/packet.hpp"
#include "its-station/link/test_link.hpp"
#include "its-station/messages/cam.hpp"
#include "its-station/messages/denm.hpp"
#include "its-station/security/tests/test_pki.hpp"
#include "its-station/station/station.hpp"

namespace tb::its::station {
namespace {

using namespace std::chrono_literals;

constexpr std::uint16_t kEthertypeGn = 0x8947;
const geodesy::Geodetic kOrigin{48.1351, 11.5820, 0.0};
/// The world (a scenario with a pinned start time) runs a year behind the host's clock: what the
/// station dates must come from its fixes, not from the host.
constexpr clock::Duration kWorldBehindHost = std::chrono::hours{24 * 365};

/// The contract's MAC address of a station: 02:00 and its StationID, big-endian.
link::MacAddress mac_of(std::uint32_t id) {
  return {0x02,
          0x00,
          static_cast<std::uint8_t>(id >> 24),
          static_cast<std::uint8_t>(id >> 16),
          static_cast<std::uint8_t>(id >> 8),
          static_cast<std::uint8_t>(id)};
}

struct Published {
  std::string topic;
  nlohmann::json payload;
};

class RecordingSink final : public tb::mqtt::MqttSink {
 public:
  void publish(std::string_view topic, std::string payload, tb::mqtt::Qos, bool) override {
    published.push_back({std::string(topic), nlohmann::json::parse(payload)});
  }
  std::vector<Published> on(const std::string& topic) const {
    std::vector<Published> r;
    for (const auto& p : published)
      if (p.topic == topic)
        r.push_back(p);
    return r;
  }
  std::vector<Published> published;
};

/// A scripted vehicle as the scenario describes it: the default car (4.255 m × 1.799 m), its
/// GNSS antenna at the centre of its bounding box.
scenario::Vehicle car(std::uint32_t id, scenario::StationKind kind = scenario::StationKind::kFull) {
  scenario::Vehicle v;
  v.id = "v" + std::to_string(id);
  v.station_id = id;
  v.station_kind = kind;
  return v;
}

/// A pooled station's vehicle as the scenario's defaults make it: no LCRW, no MQTT.
scenario::Vehicle pooled_car(std::uint32_t id) {
  scenario::Vehicle v = car(id);
  v.station_kind = scenario::StationKind::kPooled;
  v.station_lcrw = false;
  v.station_mqtt = false;
  return v;
}

/// One station over fake ports. Every station of a test shares the host runtime, as the pooled
/// stations of a station-host share its io thread.
struct FakeStation {
  /// @p security: signs and verifies (null: unsecured); @p pooled: the vehicle's station is a
  /// pooled one, without LCRW.
  FakeStation(clock::ManualRuntime& host, std::uint32_t id, bool with_mqtt,
              security::SecurityEntity* security = nullptr, bool pooled = false)
      : vehicle(pooled ? pooled_car(id) : car(id)),
        its_clock(host),
        link(mac_of(id)),
        station(StationPorts{host, its_clock, gnss, nullptr, link, security,
                             with_mqtt ? &sink : nullptr},
                make_station_config(id, nullptr, &vehicle, StationOverrides{})) {}

  /// A receiver fix with the antenna (the bounding box's centre) at @p east, @p north metres
  /// from kOrigin, moving along @p course_deg at @p speed_mps, dated now in the world.
  clock::WallTime fix(const clock::ManualRuntime& host, double east, double north,
                      double course_deg, double speed_mps) {
    const auto g = geodesy::LocalFrame(kOrigin).to_geodetic({east, north, 0.0});
    facilities::PositionFix f;
    f.time = host.wall_now() - kWorldBehindHost;
    f.received = host.steady_now();
    f.latitude_deg = g.latitude_deg;
    f.longitude_deg = g.longitude_deg;
    f.speed_mps = speed_mps;
    f.course_deg = course_deg;
    f.heading_deg = course_deg;
    f.position_confidence = facilities::PositionFix::Ellipse{2.0, 2.0, 0.0};
    f.speed_confidence_mps = 0.1;
    f.heading_confidence_deg = 1.0;
    gnss.inject(f);
    return f.time;
  }

  scenario::Vehicle vehicle;
  clock::GnssDisciplinedRuntime its_clock;
  facilities::InjectedPositionProvider gnss;
  link::TestLink link;
  RecordingSink sink;
  Station station;
};

/// A GN frame off the link, down to its BTP-B destination port and the message's bytes.
struct Decoded {
  geonet::Packet gn;
  std::uint16_t btp_port = 0;
  std::span<const std::uint8_t> message;
};
std::optional<Decoded> decode(const link::TestLink::SentFrame& f) {
  if (f.ethertype != kEthertypeGn)
    return std::nullopt;
  auto gn = geonet::parse_packet(f.payload);
  if (!gn)
    return std::nullopt;
  auto btp = btp::parse_header_b(gn->payload);
  if (!btp)
    return std::nullopt;
  return Decoded{*gn, btp->destination_port, gn->payload.subspan(btp::kHeaderSize)};
}

std::vector<messages::Cam> cams_sent(link::TestLink& link) {
  std::vector<messages::Cam> r;
  for (const auto& f : link.sent())
    if (const auto d = decode(f); d && d->btp_port == btp::kPortCam)
      if (auto cam = messages::decode_cam(d->message))
        r.push_back(*cam);
  return r;
}

std::vector<messages::Denm> denms_sent(link::TestLink& link, bool* all_geobroadcast) {
  std::vector<messages::Denm> r;
  *all_geobroadcast = true;
  for (const auto& f : link.sent())
    if (const auto d = decode(f); d && d->btp_port == btp::kPortDenm) {
      if (auto denm = messages::decode_denm(d->message)) {
        r.push_back(*denm);
        *all_geobroadcast &= std::holds_alternative<geonet::GbcHeader>(d->gn.extended);
      }
    }
  return r;
}

TEST(Station, SendsACamWhenAFixMakesOneDue) {
  clock::ManualRuntime host;
  FakeStation s(host, 1001, /*with_mqtt=*/true);
  s.station.start();
  host.advance(300ms);
  EXPECT_TRUE(cams_sent(s.link).empty()) << "a CAM without a fix";

  // Heading north at 10 m/s, the antenna 20 m east and 30 m north of the origin.
  const clock::WallTime world = s.fix(host, 20.0, 30.0, 0.0, 10.0);
  const auto cams = cams_sent(s.link);
  ASSERT_EQ(cams.size(), 1u) << "the first fix makes the first CAM due (EN 302 637-2 6.1.3)";
  const messages::Cam& cam = cams[0];
  EXPECT_EQ(cam.header.stationID, 1001u);
  // generationDeltaTime names the fix's instant: ms since 2004-01-01T00:00:00Z mod 65 536
  // (EN 302 637-2 B.3), on the world's time, not the host's.
  const std::int64_t world_ms =
      std::chrono::duration_cast<std::chrono::milliseconds>(world.time_since_epoch()).count();
  constexpr std::int64_t k2004UnixMs = 1'072'915'200'000;
  EXPECT_EQ(cam.cam.generationDeltaTime, (world_ms - k2004UnixMs) % 65536);
  // The reference position is the front centre of the car (EN 302 637-2 B.3): half its length
  // ahead of the antenna, which sits at the centre.
  const auto front =
      geodesy::LocalFrame(kOrigin).to_geodetic({20.0, 30.0 + s.vehicle.model.length_m / 2, 0.0});
  const auto& ref = cam.cam.camParameters.basicContainer.referencePosition;
  EXPECT_NEAR(ref.latitude, std::lround(front.latitude_deg * 1e7), 2);
  EXPECT_NEAR(ref.longitude, std::lround(front.longitude_deg * 1e7), 2);
  // Sent from the station's own MAC address.
  ASSERT_FALSE(s.link.sent().empty());
  const auto gn = decode(s.link.sent().back());
  ASSERT_TRUE(gn);
  EXPECT_EQ(geonet::source_position(gn->gn.extended).address.mid, mac_of(1001));

  // The fix reaches MQTT as the station's state, and the status reports it.
  EXPECT_EQ(s.sink.on("its/1001/state").size(), 1u);
  const auto status = s.station.status();
  EXPECT_EQ(status["station_id"], 1001);
  EXPECT_EQ(status["fix"], true);
  EXPECT_EQ(status["cams_sent"], 1);

  // No new fix: the next CAM waits for one, or for T_GenCamMax (1 s) with the old fix.
  host.advance(500ms);
  EXPECT_EQ(cams_sent(s.link).size(), 1u);
  s.station.stop();
}

TEST(Station, WarnsOfANeighbourOnACollisionCourseFromItsCam) {
  clock::ManualRuntime host;
  FakeStation own(host, 1001, /*with_mqtt=*/true);
  FakeStation other(host, 2002, /*with_mqtt=*/false);
  EXPECT_TRUE(own.station.config().lcrw);
  own.station.start();
  other.station.start();

  // Head-on in one lane: the own car northbound at the origin, the other 80 m ahead
  // southbound, both at 15 m/s, both states of this instant.
  constexpr double kDistance = 80.0;
  constexpr double kSpeed = 15.0;
  const clock::WallTime world = own.fix(host, 0.0, 0.0, 0.0, kSpeed);
  EXPECT_TRUE(own.sink.on("its/1001/app/lcrw").empty()) << "a warning without a neighbour";
  other.fix(host, 0.0, kDistance, 180.0, kSpeed);
  const auto cams = cams_sent(other.link);
  ASSERT_EQ(cams.size(), 1u);

  // The other's CAM, as the radio hands it over.
  const std::size_t own_frames_before = own.link.sent().size();
  for (const auto& f : other.link.sent())
    own.link.inject(other.link.address(), f.destination, f.ethertype, f.payload, host.wall_now());

  ASSERT_EQ(own.station.ldm().neighbours().size(), 1u);
  EXPECT_TRUE(own.station.ldm().neighbours().contains(2002));

  // What the world says: bumper to bumper the centres' distance less two half lengths, closed at
  // the sum of the speeds.
  const double length = own.vehicle.model.length_m;
  const double gap = kDistance - length;
  const double ttc = gap / (2 * kSpeed);
  ASSERT_LT(ttc, apps::LcrwConfig{}.ttc_warning_s);

  const auto warnings = own.sink.on("its/1001/app/lcrw");
  ASSERT_EQ(warnings.size(), 1u);
  const auto& w = warnings[0].payload["message"];
  EXPECT_EQ(w["event"], "raised");
  EXPECT_EQ(w["other_station_id"], 2002);
  EXPECT_EQ(w["collision_case"], "frontal");
  EXPECT_NEAR(w["ttc_s"].get<double>(), ttc, 0.01);
  EXPECT_NEAR(w["distance_m"].get<double>(), gap, 0.05);
  EXPECT_NEAR(w["relative_speed_mps"].get<double>(), 2 * kSpeed, 0.05);
  // Both states are of the world's instant: the received CAM is dated on the ITS clock, not on
  // the host's (a year ahead here).
  const auto world_ms =
      std::chrono::duration_cast<std::chrono::milliseconds>(world.time_since_epoch()).count();
  EXPECT_EQ(w["own_state_time"], world_ms);
  EXPECT_EQ(w["other_state_time"], world_ms);

  // And the risk goes on the air as a collision-risk DENM (cause 97), geo-broadcast.
  ASSERT_GT(own.link.sent().size(), own_frames_before);
  bool geobroadcast = false;
  const auto denms = denms_sent(own.link, &geobroadcast);
  ASSERT_EQ(denms.size(), 1u);
  EXPECT_TRUE(geobroadcast);
  EXPECT_EQ(denms[0].header.stationID, 1001u);
  EXPECT_EQ(denms[0].denm.management.actionID.originatingStationID, 1001u);
  ASSERT_TRUE(denms[0].denm.situation);
  EXPECT_EQ(denms[0].denm.situation->eventType.causeCode, 97);

  own.station.stop();
  other.station.stop();
}

// A TTC that will cross the threshold before the next fix is met by a timer at the predicted
// onset, not a fix period late.
TEST(Station, RaisesTheWarningAtThePredictedOnsetBetweenFixes) {
  clock::ManualRuntime host;
  FakeStation own(host, 1001, /*with_mqtt=*/true);
  FakeStation other(host, 2002, /*with_mqtt=*/false);
  own.station.start();
  other.station.start();

  // Head-on at 15 m/s each, TTC 3.05 s now: 50 ms above the 3 s threshold, half a fix period.
  constexpr double kSpeed = 15.0;
  const double threshold = apps::LcrwConfig{}.ttc_warning_s;
  const double ttc_now = threshold + 0.05;
  const double distance = own.vehicle.model.length_m + ttc_now * 2 * kSpeed;
  own.fix(host, 0.0, 0.0, 0.0, kSpeed);
  other.fix(host, 0.0, distance, 180.0, kSpeed);
  for (const auto& f : other.link.sent())
    own.link.inject(other.link.address(), f.destination, f.ethertype, f.payload, host.wall_now());
  ASSERT_EQ(own.station.ldm().neighbours().size(), 1u);
  EXPECT_TRUE(own.sink.on("its/1001/app/lcrw").empty()) << "TTC above the threshold";

  host.advance(40ms);
  EXPECT_TRUE(own.sink.on("its/1001/app/lcrw").empty()) << "raised before the onset";
  host.advance(20ms);  // past the onset, still 40 ms before the next fix
  const auto warnings = own.sink.on("its/1001/app/lcrw");
  ASSERT_EQ(warnings.size(), 1u) << "no evaluation at the predicted onset";
  const auto& w = warnings[0].payload["message"];
  EXPECT_EQ(w["event"], "raised");
  EXPECT_EQ(w["other_station_id"], 2002);
  EXPECT_NEAR(w["ttc_s"].get<double>(), threshold, 0.01);
  own.station.stop();
  other.station.stop();
}

TEST(Station, APooledStationRunsNoLcrwUnlessAsked) {
  clock::ManualRuntime host;
  scenario::Vehicle v = car(3003);
  v.station_kind = scenario::StationKind::kPooled;
  v.station_lcrw = false;
  v.station_mqtt = false;
  const auto config = make_station_config(3003, nullptr, &v, StationOverrides{});
  EXPECT_FALSE(config.lcrw);
  EXPECT_FALSE(config.mqtt);
  v.station_lcrw = true;
  EXPECT_TRUE(make_station_config(3003, nullptr, &v, StationOverrides{}).lcrw);
  StationOverrides no_lcrw;
  no_lcrw.no_lcrw = true;
  EXPECT_FALSE(make_station_config(3003, nullptr, &v, no_lcrw).lcrw);
}

// A pooled station traces what it sends but not what it hears (docs/tracing.md): 300 in range
// would write 300 × 800 reception records a second (issue 33). A full one traces both.
TEST(Station, APooledStationTracesNoReceptions) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("station-rx-trace-" + std::to_string(::getpid()) + ".jsonl");
  std::filesystem::remove(path);
  // The services write to the process's tracer, as in its-station and station-host; it stays
  // on for this test binary's later tests (records of their own, in a file removed below).
  trace::configure(path.string(), "its-station");
  clock::ManualRuntime host;
  FakeStation full(host, 1001, /*with_mqtt=*/false);
  FakeStation pooled(host, 2002, /*with_mqtt=*/false, nullptr, /*pooled=*/true);
  EXPECT_TRUE(full.station.config().ca.trace_receptions);
  EXPECT_FALSE(pooled.station.config().ca.trace_receptions);
  full.station.start();
  pooled.station.start();
  full.fix(host, 0.0, 0.0, 0.0, 10.0);
  pooled.fix(host, 0.0, 50.0, 180.0, 10.0);
  for (const auto& f : pooled.link.sent())
    full.link.inject(pooled.link.address(), f.destination, f.ethertype, f.payload, host.wall_now());
  for (const auto& f : full.link.sent())
    pooled.link.inject(full.link.address(), f.destination, f.ethertype, f.payload, host.wall_now());
  ASSERT_TRUE(full.station.ldm().neighbour(2002));
  ASSERT_TRUE(pooled.station.ldm().neighbour(1001)) << "the pooled station hears, untraced";
  trace::global().flush();

  std::map<std::pair<std::string, std::uint32_t>, int> records;  // (event, station) → count
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    const auto r = nlohmann::json::parse(line);
    if (r.contains("station"))
      ++records[{r["ev"].get<std::string>(), r["station"].get<std::uint32_t>()}];
  }
  std::filesystem::remove(path);
  EXPECT_EQ((records[{"its.cam_rx", 1001}]), 1);
  EXPECT_EQ((records[{"its.ldm", 1001}]), 1);
  EXPECT_EQ((records[{"its.cam_rx", 2002}]), 0);
  EXPECT_EQ((records[{"its.ldm", 2002}]), 0);
  // What a pooled station sends is traced as a full one's.
  EXPECT_EQ((records[{"its.cam_tx", 2002}]), 1);
  EXPECT_EQ((records[{"its.cam_tx", 1001}]), 1);
  full.station.stop();
  pooled.station.stop();
}

TEST(Station, APooledStationWithoutLcrwTakesSignedCamsWithoutVerifyingThem) {
  clock::ManualRuntime host;
  security::testing::TestPki pki{host.wall_now() - kWorldBehindHost};
  const auto sender_security = pki.entity(security::SecurityMode::kSigned);
  const auto full_security = pki.entity(security::SecurityMode::kSigned);
  const auto pooled_security = pki.entity(security::SecurityMode::kSigned);
  // Each checked the AA when it was made.
  const auto full_base = full_security->verifier().ecdsa_verifications();
  const auto pooled_base = pooled_security->verifier().ecdsa_verifications();
  FakeStation sender(host, 1001, false, sender_security.get());
  FakeStation full(host, 2002, false, full_security.get());
  FakeStation pooled(host, 3003, false, pooled_security.get(), /*pooled=*/true);
  EXPECT_EQ(full.station.config().verify_policy, security::VerifyPolicy::kEvery);
  EXPECT_EQ(pooled.station.config().verify_policy, security::VerifyPolicy::kOnDemand);
  for (auto* s : {&sender, &full, &pooled})
    s->station.start();
  // Every ITS clock on the world's time, then the sender's first CAM (its AT in it).
  full.fix(host, 0.0, 50.0, 0.0, 10.0);
  pooled.fix(host, 0.0, 100.0, 0.0, 10.0);
  sender.fix(host, 0.0, 0.0, 0.0, 10.0);
  ASSERT_FALSE(sender.link.sent().empty());
  for (auto* r : {&full, &pooled})
    for (const auto& f : sender.link.sent())
      r->link.inject(sender.link.address(), f.destination, f.ethertype, f.payload, host.wall_now());

  // Both know the sender; the full station checked the AT and the CAM, the pooled one the AT
  // only (cached for the DENMs it would verify).
  EXPECT_TRUE(full.station.ldm().neighbours().contains(1001));
  EXPECT_TRUE(pooled.station.ldm().neighbours().contains(1001));
  EXPECT_EQ(full_security->verifier().count(security::VerifyResult::kOk), 1u);
  EXPECT_EQ(full_security->verifier().ecdsa_verifications() - full_base, 2u);
  EXPECT_EQ(pooled_security->verifier().count(security::VerifyResult::kOk), 0u);
  EXPECT_EQ(pooled_security->verifier().count(security::VerifyResult::kNotVerified), 1u);
  EXPECT_EQ(pooled_security->verifier().ecdsa_verifications() - pooled_base, 1u);
  const auto status = pooled.station.status();
  EXPECT_EQ(status["security"]["verify_policy"], "on-demand");
  EXPECT_EQ(status["security"]["verify"]["not_verified"], 1);
  for (auto* s : {&sender, &full, &pooled})
    s->station.stop();
}

}  // namespace
}  // namespace tb::its::station
