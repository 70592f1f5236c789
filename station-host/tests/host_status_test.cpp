// The status file of a host whose two stations hear each other through the host's own loopback
// (kernel forwarding): each lists the other, counts what it sent and received, and the file is
// whole JSON, written by rename.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <memory>

#include <nlohmann/json.hpp>

#include "common/clock/gnss_disciplined_runtime.hpp"
#include "common/geodesy/local_frame.hpp"
#include "station-host/app/host_status.hpp"

namespace tb::host {
namespace {

using namespace std::chrono_literals;

struct NullOutput final : FrameOutput {
  std::error_code send_frame(std::span<const std::uint8_t>) override { return {}; }
};

struct Pooled {
  Pooled(clock::ManualRuntime& rt, PooledLinks& links, std::uint32_t id)
      : vehicle(make_vehicle(id)),
        its_clock(rt),
        station(its::station::StationPorts{rt, its_clock, gnss, nullptr, links.link(id), nullptr,
                                           nullptr},
                its::station::make_station_config(id, nullptr, &vehicle, {})) {
    station.start();
  }
  static scenario::Vehicle make_vehicle(std::uint32_t id) {
    scenario::Vehicle v;
    v.id = "v" + std::to_string(id);
    v.station_id = id;
    v.station_kind = scenario::StationKind::kPooled;
    v.station_lcrw = false;
    v.station_mqtt = false;
    return v;
  }
  void fix(const clock::ManualRuntime& rt, double east) {
    const auto g = geodesy::LocalFrame({48.0, 11.0, 0.0}).to_geodetic({east, 0.0, 0.0});
    its::facilities::PositionFix f;
    f.time = rt.wall_now();
    f.received = rt.steady_now();
    f.latitude_deg = g.latitude_deg;
    f.longitude_deg = g.longitude_deg;
    f.speed_mps = 10.0;
    f.course_deg = 90.0;
    f.heading_deg = 90.0;
    f.position_confidence = its::facilities::PositionFix::Ellipse{2.0, 2.0, 0.0};
    f.speed_confidence_mps = 0.1;
    f.heading_confidence_deg = 1.0;
    gnss.inject(f);
  }
  scenario::Vehicle vehicle;
  clock::GnssDisciplinedRuntime its_clock;
  its::facilities::InjectedPositionProvider gnss;
  its::station::Station station;
};

TEST(HostStatus, ListsEachStationsNeighboursAndCounts) {
  clock::ManualRuntime rt;
  NullOutput out;
  bool flush_due = false;
  PooledLinks links(out, rt, /*loop_back=*/true, [&] { flush_due = true; });
  Pooled a(rt, links, 3001), b(rt, links, 3002);
  for (int k = 0; k < 20; ++k) {
    a.fix(rt, 10.0 + 5.0 * k);
    b.fix(rt, 50.0 + 5.0 * k);
    if (flush_due)
      links.flush();
    rt.advance(100ms);
  }
  const auto path = std::filesystem::path(::testing::TempDir()) / "host_status_test.json";
  std::filesystem::remove(path);
  const std::vector<const its::station::Station*> stations{&a.station, &b.station};
  const std::vector<const its::security::SecurityEntity*> security{nullptr, nullptr};
  HostStatus(path.string())
      .write(stations, security, links.counters(), HostSocketStats{}, StateFeed::Counters{});
  EXPECT_FALSE(std::filesystem::exists(path.string() + ".tmp"));
  std::ifstream in(path);
  const auto j = nlohmann::json::parse(in, nullptr, false);
  ASSERT_TRUE(j.is_object());
  ASSERT_EQ(j["stations"].size(), 2u);
  const auto& sa = j["stations"][0];
  const auto& sb = j["stations"][1];
  EXPECT_EQ(sa["station_id"], 3001);
  EXPECT_EQ(sa["neighbour_ids"], nlohmann::json::array({3002}));
  EXPECT_EQ(sb["neighbour_ids"], nlohmann::json::array({3001}));
  EXPECT_EQ(sa["neighbours"], 1);
  EXPECT_GT(sa["cams_sent"].get<int>(), 0);
  EXPECT_EQ(sa["cams_received"], sb["cams_sent"]);
  EXPECT_EQ(sb["cams_received"], sa["cams_sent"]);
  EXPECT_TRUE(sa["fix"].get<bool>());
  EXPECT_FALSE(sa.contains("security"));
  EXPECT_EQ(j["link"]["looped_back"].get<int>(),
            sa["cams_sent"].get<int>() + sb["cams_sent"].get<int>());
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace tb::host
