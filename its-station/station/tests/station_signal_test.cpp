// The signal application inside a Station built from fake ports (issue 34): an RSU's MAPEM and
// SPATEM, encoded with the codec from an intersection laid out here and sent through a real GN
// router and BTP, and the fixes of a car driving up to the light. What the fake MQTT sink gets is
// graded against the test's own physics: where the car's front is at each fix, and when it can
// no longer stop comfortably (issue 34's rule: 1 s reaction, 3 m/s²).

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "its-station/station/tests/signal_station_fixture.hpp"

namespace tb::its::station {
namespace {

using namespace testing;
constexpr double kReactionS = 1.0;     // issue 34's RLVW rule
constexpr double kComfortDecel = 3.0;  // m/s²

// 60 km/h towards a light that turns amber at 3 s and red at 6 s, 150 m ahead: the car cannot
// stop comfortably from 63 m on (v·1 s + v²/(2·3 m/s²)), when the light will be red on arrival.
TEST(StationSignals, WarnsACarThatCanNoLongerStopForTheRedLight) {
  SignalRun run;
  const double v = 60.0 / 3.6;
  const auto d = run.drive(150.0, 8.0, [&](double) { return v; });

  const auto signal = run.sink.on("its/1001/app/signal");
  ASSERT_FALSE(signal.empty());
  bool green = false;
  bool amber = false;
  bool red = false;
  for (const auto& s : signal) {
    if (!s.payload.contains("lane_id"))
      continue;  // left the lane ("lane": null)
    EXPECT_EQ(s.payload["intersection_id"], 100);
    EXPECT_EQ(s.payload["lane_id"], 1);
    EXPECT_EQ(s.payload["signal_group"], kGroup);
    // The stop line distance is the front's, at the fix it was computed from.
    EXPECT_NEAR(s.payload["distance_to_stop_line_m"].get<double>(), d[s.fix_index], 0.1)
        << s.payload.dump();
    const double t = s.fix_index * 0.1;
    const std::string light = s.payload["state"];
    if (t < kAmberAtS - 0.05) {
      EXPECT_EQ(light, "green") << t;
    } else if (t > kAmberAtS + 0.05 && t < kRedAtS - 0.05) {
      EXPECT_EQ(light, "amber") << t;
    } else if (t > kRedAtS + 0.05) {
      EXPECT_EQ(light, "red") << t;
    }
    green |= light == "green";
    amber |= light == "amber";
    red |= light == "red";
  }
  EXPECT_TRUE(green && amber && red);

  const auto rlvw = run.sink.on("its/1001/app/rlvw");
  ASSERT_FALSE(rlvw.empty());
  const auto& raised = rlvw.front();
  EXPECT_EQ(raised.payload["event"], "raised");
  EXPECT_EQ(raised.payload["intersection_id"], 100);
  EXPECT_EQ(raised.payload["signal_group"], kGroup);
  const double stopping = v * kReactionS + v * v / (2.0 * kComfortDecel);
  const double d_raise = d[raised.fix_index];
  // Raised at the first fix at which stopping comfortably is no longer possible: the fix before
  // (one fix period, v·0.1 s, further back) could still stop.
  EXPECT_LT(d_raise, stopping + 0.1);
  EXPECT_GT(d_raise, stopping - v * 0.1 - 0.1);
  // The driver has more than 2 s before the line (issue 34's e2e figure).
  EXPECT_GE(d_raise / v, 2.0);
  // The light on arrival, at constant speed, is red: the warning is about a real violation.
  EXPECT_GT(raised.fix_index * 0.1 + d_raise / v, kRedAtS);

  const auto status = run.station.status();
  ASSERT_TRUE(status.contains("signals")) << status.dump();
  const auto& sig = status["signals"];
  EXPECT_EQ(sig["intersections"], 1);
  EXPECT_EQ(sig["mapem_received"], 9);    // t = 0 … 8 s
  EXPECT_EQ(sig["spatem_received"], 81);  // every 100 ms
  EXPECT_EQ(sig["rlvw"], 1);
  EXPECT_TRUE(sig["rlvw_active"].get<bool>());
  ASSERT_TRUE(sig["lane"].is_object()) << sig.dump();
  EXPECT_EQ(sig["lane"]["lane"], 1);
  EXPECT_EQ(sig["lane"]["light"], "red");
}

// 30 km/h towards the same light: comfortably stoppable until 20 m before the line, and the
// driver brakes at 2 m/s² from 23 m to stand before it: never a warning.
TEST(StationSignals, NoWarningForACarThatStopsForTheLight) {
  SignalRun run;
  const double v = 30.0 / 3.6;
  const double brake = 2.0;
  const double d0 = 100.0;
  const double d_brake = v * v / (2.0 * 1.5);  // 23.1 m: a stop 5.7 m before the line at 2 m/s²
  const double t_brake = (d0 - d_brake) / v;
  const auto d = run.drive(d0, t_brake + v / brake + 1.0, [&](double t) {
    return t < t_brake ? v : std::max(0.0, v - brake * (t - t_brake));
  });
  EXPECT_GT(d.back(), 0.0);  // it stood before the line
  EXPECT_TRUE(run.sink.on("its/1001/app/rlvw").empty());
  EXPECT_FALSE(run.sink.on("its/1001/app/signal").empty());
  EXPECT_EQ(run.station.status()["signals"]["rlvw"], 0);
}

// A vehicle without the signal application does not listen: no decoding, nothing stored.
TEST(StationSignals, AStationWithoutSignalsIgnoresMapemAndSpatem) {
  SignalRun run(false);
  run.drive(150.0, 2.0, [](double) { return 60.0 / 3.6; });
  EXPECT_EQ(run.station.signal_app(), nullptr);
  EXPECT_TRUE(run.station.ldm().intersections().entries().empty());
  EXPECT_TRUE(run.sink.on("its/1001/app/signal").empty());
  EXPECT_FALSE(run.station.status().contains("signals"));
  EXPECT_GT(run.station.router().stats().delivered, 0u);  // the frames did arrive
}

// The scenario's station.signals (default on for full stations, off for pooled ones), the
// command line's --no-signal-app, and never for a road-side unit, which sends the messages.
TEST(StationSignals, WhoRunsTheSignalApplication) {
  scenario::Vehicle full = SignalRun::make_vehicle(true);
  EXPECT_TRUE(make_station_config(1, nullptr, &full, {}).signals);
  StationOverrides off;
  off.no_signals = true;
  EXPECT_FALSE(make_station_config(1, nullptr, &full, off).signals);
  StationOverrides rsu;
  rsu.station_type = 15;
  EXPECT_FALSE(make_station_config(5001, nullptr, nullptr, rsu).signals);
  EXPECT_TRUE(make_station_config(5001, nullptr, nullptr, {}).signals);
  scenario::Vehicle pooled = SignalRun::make_vehicle(false);
  pooled.station_kind = scenario::StationKind::kPooled;
  EXPECT_FALSE(make_station_config(2, nullptr, &pooled, {}).signals);
}

}  // namespace
}  // namespace tb::its::station
