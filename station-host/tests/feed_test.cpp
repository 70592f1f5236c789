#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <numbers>
#include <set>

#include <gtest/gtest.h>

#include "common/geodesy/local_frame.hpp"
#include "station-host/feed/epoch_phase.hpp"
#include "station-host/feed/state_feed.hpp"

namespace tb::host {
namespace {

using namespace std::chrono_literals;
namespace facilities = its::facilities;

const geodesy::LocalFrame& frame() {
  static const geodesy::LocalFrame f({48.0, 11.0, 500.0});
  return f;
}

constexpr std::int64_t kStartNs = 1'735'732'800'000'000'000;

scenario::Scenario make_scenario(bool ideal = true) {
  scenario::Scenario s;
  s.name = "feed";
  s.rates.gnss_hz = 10.0;
  s.rates.can_dynamics_hz = 50.0;
  s.gnss.ideal = ideal;
  if (!ideal) {
    s.gnss.white_noise_m = 1.5;
    s.gnss.bias_walk_m = 0.2;
    s.gnss.vertical_noise_m = 2.0;
  }
  for (std::uint32_t id : {3001u, 3002u}) {
    scenario::Vehicle v;
    v.id = "car" + std::to_string(id);
    v.station_id = id;
    s.vehicles.push_back(v);
  }
  return s;
}

wire::VehicleState state(std::uint32_t id, std::int64_t sim_ms, double x = 100.0,
                         double y = -50.0) {
  wire::VehicleState s;
  s.station_id = id;
  s.tick = static_cast<std::uint64_t>(sim_ms / 10 + 1000);
  s.sim_time_ns = sim_ms * 1'000'000;
  s.position = {x, y, 1.5};
  s.velocity = {0.0f, 10.0f, 0.0f};  // due north
  s.speed = 10.0f;
  s.yaw = static_cast<float>(std::numbers::pi / 2);
  return s;
}

std::vector<std::uint8_t> batch(std::initializer_list<wire::VehicleState> states,
                                std::int64_t world_start = kStartNs) {
  return wire::encode_batch(std::vector<wire::VehicleState>(states), world_start);
}

struct Recorder {
  std::vector<facilities::PositionFix> fixes;
  std::vector<bool> availability;
  explicit Recorder(facilities::PositionProvider& p) {
    p.on_fix([this](const facilities::PositionFix& f) { fixes.push_back(f); });
    p.on_availability([this](bool a) { availability.push_back(a); });
  }
};

TEST(GpsdReportOf, IsWhatGpsdReportsOfTheAgentsEpoch) {
  emu::gnss::Fix fix;
  fix.time = clock::from_unix_ns(kStartNs + 300'000'000);
  fix.position = {48.001, 11.002, 510.5};
  fix.speed_mps = 12.5;
  fix.course_deg = 359.996;  // RMC writes 0.00
  fix.hdop = 1.1;
  fix.vdop = 1.7;
  fix.sigma_lat_m = 0.8;
  fix.sigma_lon_m = 1.6;
  fix.sigma_alt_m = 2.5;
  fix.sky.resize(5);
  const facilities::GpsdReport r = gpsd_report_of(fix);
  ASSERT_TRUE(r.mode);
  EXPECT_EQ(*r.mode, facilities::GpsdMode::k3D);
  EXPECT_EQ(r.time, fix.time);
  EXPECT_DOUBLE_EQ(r.latitude_deg, 48.001);
  EXPECT_DOUBLE_EQ(r.altitude_hae_m, 510.5);
  EXPECT_DOUBLE_EQ(r.track_deg, 0.0);
  EXPECT_DOUBLE_EQ(r.eph_m, 1.1 * 19.0);
  EXPECT_DOUBLE_EQ(r.epv_m, 1.7 * 23.0);
  ASSERT_TRUE(r.gst);
  EXPECT_DOUBLE_EQ(r.gst->semi_major_sigma_m, 1.6);
  EXPECT_DOUBLE_EQ(r.gst->semi_minor_sigma_m, 0.8);
  EXPECT_DOUBLE_EQ(r.gst->orientation_deg, 90.0);

  fix.sky.resize(3);
  EXPECT_EQ(*gpsd_report_of(fix).mode, facilities::GpsdMode::k2D);
  fix.valid = false;
  EXPECT_EQ(*gpsd_report_of(fix).mode, facilities::GpsdMode::kNoFix);
}

TEST(StateGnssReceiver, PublishesTheFixOfEachEpochWithGpsdsConfidences) {
  clock::ManualRuntime runtime;
  emu::gnss::AgentConfig c;
  c.station_id = 3001;
  c.rate_hz = 10.0;
  c.start_time = clock::from_unix_ns(kStartNs);
  c.errors.hdop = 0.9;
  c.errors.vdop = 1.2;
  StateGnssReceiver rx(c, frame(), runtime);
  Recorder rec(rx);
  for (std::int64_t ms = 0; ms < 1000; ms += 10) {
    runtime.advance(10ms);
    rx.on_state(state(3001, ms));
  }
  ASSERT_EQ(rec.fixes.size(), 10u);  // 10 Hz out of 100 Hz states
  EXPECT_EQ(rec.availability, std::vector<bool>{true});
  const facilities::PositionFix& f = rec.fixes[3];
  // The fix time is the state's time on the world clock, as the agent writes it into NMEA.
  EXPECT_EQ(clock::to_unix_ns(f.time), kStartNs + 300'000'000);
  EXPECT_EQ(f.received, clock::SteadyTime{} + 310ms);
  const geodesy::Geodetic truth = frame().to_geodetic({100.0, -50.0, 1.5});
  EXPECT_NEAR(f.latitude_deg, truth.latitude_deg, 1e-9);
  EXPECT_NEAR(f.longitude_deg, truth.longitude_deg, 1e-9);
  ASSERT_TRUE(f.altitude_m);
  EXPECT_NEAR(*f.altitude_m, truth.altitude_m, 1e-6);
  ASSERT_TRUE(f.speed_mps && f.course_deg && f.heading_deg);
  EXPECT_NEAR(*f.speed_mps, 10.0, 1e-6);
  EXPECT_NEAR(*f.course_deg, 0.0, 1e-6);
  EXPECT_EQ(*f.heading_deg, *f.course_deg);
  // Ideal errors: the GST ellipse is 0; altitude and speed confidences from the DOPs.
  ASSERT_TRUE(f.position_confidence);
  EXPECT_DOUBLE_EQ(f.position_confidence->semi_major_m, 0.0);
  ASSERT_TRUE(f.altitude_confidence_m && f.speed_confidence_mps && f.heading_confidence_deg);
  EXPECT_DOUBLE_EQ(*f.altitude_confidence_m, 1.2 * 23.0);
  EXPECT_DOUBLE_EQ(*f.speed_confidence_mps, facilities::speed_confidence_95(0.9));
  EXPECT_DOUBLE_EQ(*f.heading_confidence_deg,
                   facilities::heading_confidence_95(10.0, *f.speed_confidence_mps));
}

TEST(StateGnssReceiver, LosesTheFixWhenStatesStopAndInFixLossWindows) {
  clock::ManualRuntime runtime;
  emu::gnss::AgentConfig c;
  c.station_id = 3001;
  c.start_time = clock::from_unix_ns(kStartNs);
  c.errors.fix_loss.push_back({1.0, 2.0});
  StateGnssReceiver rx(c, frame(), runtime);
  Recorder rec(rx);
  rx.on_state(state(3001, 0));
  runtime.advance(1900ms);
  EXPECT_EQ(rec.availability, std::vector<bool>{true});
  runtime.advance(200ms);  // 2 s without an epoch: stale, as a silent gpsd
  EXPECT_EQ(rec.availability, (std::vector<bool>{true, false}));
  rx.on_state(state(3001, 500));
  rx.on_state(state(3001, 1500));  // inside the fix-loss window: mode 1, no fix
  EXPECT_EQ(rec.availability, (std::vector<bool>{true, false, true, false}));
  EXPECT_EQ(rec.fixes.size(), 2u);
}

TEST(StateFeed, SeedsEachStationsErrorsAsTheEmulatorSeedsItsAgent) {
  const scenario::Scenario s = make_scenario(/*ideal=*/false);
  clock::ManualRuntime runtime;
  StateFeed feed(s, frame(), runtime, 77);
  Recorder rec(*feed.add(3002).gnss);
  emu::gnss::AgentConfig c;
  c.station_id = 3002;
  c.rate_hz = s.rates.gnss_hz;
  c.start_time = clock::from_unix_ns(kStartNs);
  c.errors = s.gnss;
  c.seed = 77;
  c.epoch_offset = epoch_phase(3002, 100ms);
  emu::gnss::GpsAgent agent(c, frame());
  for (std::int64_t ms = 0; ms < 2000; ms += 100) {
    ASSERT_TRUE(feed.handle_datagram(batch({state(3001, ms), state(3002, ms)})));
    ASSERT_TRUE(agent.on_state(state(3002, ms)));
    ASSERT_FALSE(rec.fixes.empty());
    EXPECT_EQ(rec.fixes.back().latitude_deg, agent.last_fix().position.latitude_deg);
    EXPECT_EQ(rec.fixes.back().longitude_deg, agent.last_fix().position.longitude_deg);
    EXPECT_EQ(rec.fixes.back().time, agent.last_fix().time);
  }
  EXPECT_EQ(rec.fixes.size(), 20u);
  EXPECT_NE(rec.fixes.back().position_confidence->semi_major_m, 0.0);
  EXPECT_EQ(feed.counters().states, 20u);
  EXPECT_EQ(feed.counters().other_station, 20u);  // 3001 is not added
}

TEST(StateFeed, StampsFixesOnTheWorldClockThatCameWithTheStates) {
  scenario::Scenario s = make_scenario();
  s.start_time = clock::from_unix_ns(1'000'000'000'000'000'000);  // the states' own wins
  clock::ManualRuntime runtime;
  StateFeed feed(s, frame(), runtime, 1);
  Recorder rec(*feed.add(3001).gnss);
  feed.handle_datagram(batch({state(3001, 1200)}));
  ASSERT_EQ(rec.fixes.size(), 1u);
  EXPECT_EQ(clock::to_unix_ns(rec.fixes[0].time), kStartNs + 1'200'000'000);
  // Without a start time in the batch the scenario's pinned one applies.
  StateFeed pinned(s, frame(), runtime, 1);
  Recorder rec2(*pinned.add(3001).gnss);
  pinned.handle_datagram(batch({state(3001, 1200)}, wire::kUnknownWorldStart));
  ASSERT_EQ(rec2.fixes.size(), 1u);
  EXPECT_EQ(clock::to_unix_ns(rec2.fixes[0].time), 1'000'000'000'000'000'000 + 1'200'000'000);
}

TEST(StateFeed, RefusesUnknownStationsAndMalformedDatagrams) {
  const scenario::Scenario s = make_scenario();
  clock::ManualRuntime runtime;
  StateFeed feed(s, frame(), runtime, 1);
  EXPECT_THROW(feed.add(4242), std::invalid_argument);
  feed.add(3001);
  EXPECT_THROW(feed.add(3001), std::invalid_argument);
  std::vector<std::uint8_t> bytes = batch({state(3001, 0)});
  bytes.pop_back();
  EXPECT_FALSE(feed.handle_datagram(bytes));
  EXPECT_FALSE(feed.handle_datagram({}));
  EXPECT_EQ(feed.counters().malformed, 2u);
  EXPECT_EQ(feed.counters().states, 0u);
}

TEST(EpochPhase, LiesInThePeriodRepeatsAndFillsItEvenly) {
  constexpr auto kPeriod = std::chrono::nanoseconds{100'000'000};
  // Ids as a host gets them: consecutive, every second one (two nodes round-robin), every third.
  for (const std::uint32_t step : {1u, 2u, 3u}) {
    for (const std::size_t n : {29u, 290u}) {
      std::vector<std::int64_t> phases;
      for (std::size_t i = 0; i < n; ++i) {
        const auto id = static_cast<std::uint32_t>(3001 + i * step);
        const auto p = epoch_phase(id, kPeriod);
        ASSERT_GE(p.count(), 0);
        ASSERT_LT(p, kPeriod);
        EXPECT_EQ(p, epoch_phase(id, kPeriod));  // from the id alone: runs repeat
        phases.push_back(p.count());
      }
      std::sort(phases.begin(), phases.end());
      // n evenly spread points on the circle of the period are period / n apart; no gap, the
      // one across the period's end included, may be a third of that or three times it.
      const double even = static_cast<double>(kPeriod.count()) / static_cast<double>(n);
      phases.push_back(phases.front() + kPeriod.count());
      for (std::size_t i = 1; i < phases.size(); ++i) {
        const auto gap = static_cast<double>(phases[i] - phases[i - 1]);
        EXPECT_GT(gap, even / 3) << "step " << step << ", n " << n << ", gap " << i;
        EXPECT_LT(gap, even * 3) << "step " << step << ", n " << n << ", gap " << i;
      }
    }
  }
}

/// A host's 29 pooled stations on 100 Hz states for 3 s: who gets a fix at which state.
struct SpreadRun {
  static constexpr std::size_t kStations = 29;
  std::vector<std::uint32_t> ids;
  std::map<std::int64_t, std::set<std::uint32_t>> fixed_at_ms;  ///< state tick → stations
  std::map<std::uint32_t, std::vector<facilities::PositionFix>> fixes;
  std::map<std::uint32_t, std::vector<std::int64_t>> fix_tick_ms;

  SpreadRun() {
    scenario::Scenario s = make_scenario();
    s.vehicles.clear();
    for (std::size_t i = 0; i < kStations; ++i) {
      scenario::Vehicle v;
      v.station_id = static_cast<std::uint32_t>(3004 + 2 * i);  // node 1's half of a ring
      v.id = "car" + std::to_string(v.station_id);
      s.vehicles.push_back(v);
      ids.push_back(v.station_id);
    }
    clock::ManualRuntime runtime;
    StateFeed feed(s, frame(), runtime, 1);
    std::int64_t now_ms = 0;
    for (const std::uint32_t id : ids)
      feed.add(id).gnss->on_fix([this, id, &now_ms](const facilities::PositionFix& f) {
        fixes[id].push_back(f);
        fix_tick_ms[id].push_back(now_ms);
        fixed_at_ms[now_ms].insert(id);
      });
    for (now_ms = 0; now_ms < 3000; now_ms += 10) {
      runtime.advance(10ms);
      std::vector<wire::VehicleState> states;
      for (const std::uint32_t id : ids)
        // Each car moves 0.1 m per tick: every state differs from the one before.
        states.push_back(state(id, now_ms, 100.0 + static_cast<double>(now_ms) / 100.0));
      EXPECT_TRUE(feed.handle_datagram(wire::encode_batch(states, kStartNs)));
    }
  }
};

TEST(StateFeed, SpreadsItsStationsEpochsOverThePeriod) {
  const SpreadRun run;
  // Before: all 29 at every 100 ms tick. Now no tick (10 ms of states) carries more than one
  // more than an even share over the period's 10 ticks; the very first state is every
  // station's first epoch.
  const std::size_t even = (SpreadRun::kStations + 9) / 10;
  for (const auto& [ms, stations] : run.fixed_at_ms) {
    if (ms == 0)
      continue;
    EXPECT_LE(stations.size(), even + 1) << "tick at " << ms << " ms";
  }
  // Every tick of the period is used by some station.
  std::set<std::int64_t> ticks_in_period;
  for (const auto& [ms, stations] : run.fixed_at_ms)
    if (ms != 0)
      ticks_in_period.insert(ms % 100);
  EXPECT_EQ(ticks_in_period.size(), 10u);
}

TEST(StateFeed, EachSpreadStationStillGetsOneFixPerPeriodOfItsNewestState) {
  const SpreadRun run;
  for (const std::uint32_t id : run.ids) {
    const auto& ticks = run.fix_tick_ms.at(id);
    const auto& fixes = run.fixes.at(id);
    // The station's own instant: its first grid point after the start, to the next state
    // (the states come every 10 ms).
    const auto phase_ms = static_cast<double>(epoch_phase(id, 100ms).count()) / 1e6;
    const auto grid = static_cast<std::int64_t>(std::ceil(phase_ms / 10.0)) * 10;
    const std::int64_t first = grid == 0 ? 100 : grid;
    // The first state's epoch, then one per period up to the last state (2990 ms).
    ASSERT_EQ(ticks.size(), static_cast<std::size_t>(1 + (2990 - first) / 100 + 1)) << id;
    EXPECT_EQ(ticks[1], first) << id;
    for (std::size_t i = 0; i < ticks.size(); ++i) {
      // The fix describes the state that made it, at the instant it came: the age of the
      // newest fix at a CA check is 0, as with the whole-period grid.
      EXPECT_EQ(clock::to_unix_ns(fixes[i].time), kStartNs + ticks[i] * 1'000'000) << id;
      EXPECT_EQ(fixes[i].received, clock::SteadyTime{} + std::chrono::milliseconds{ticks[i] + 10});
      // One check per period (the CA check runs at each fix): after the first, 100 ms apart.
      // So a change of the vehicle's state is in a fix, and can be in a CAM, at most one
      // period later, as before.
      if (i >= 2) {
        EXPECT_EQ(ticks[i] - ticks[i - 1], 100) << id << " fix " << i;
      }
    }
  }
}

TEST(StateVehicleData, GivesWhatTheCanFeedGivesAFullStation) {
  clock::ManualRuntime runtime;
  StateVehicleData vd(50.0, 15.0, runtime);
  std::vector<facilities::VehicleData> got;
  vd.on_update([&](const facilities::VehicleData& d) { got.push_back(d); });
  for (std::int64_t ms = 0; ms < 100; ms += 10) {
    wire::VehicleState st = state(3001, ms);
    st.speed = -2.0f;
    st.yaw_rate = 0.1f;
    st.acceleration = {1.5f, -0.5f, 0.0f};
    st.steering_angle = 0.02f;
    st.controls.brake = 0.3f;
    st.lights = wire::kHazard | wire::kLowBeam | wire::kSiren;
    vd.on_state(st);
  }
  ASSERT_EQ(got.size(), 5u);  // 50 Hz out of 100 Hz states
  const facilities::VehicleData& d = got.back();
  EXPECT_DOUBLE_EQ(*d.speed_mps, -2.0);
  EXPECT_TRUE(*d.reversing);
  EXPECT_NEAR(*d.yaw_rate_dps, 0.1 * 180.0 / std::numbers::pi, 1e-5);
  EXPECT_DOUBLE_EQ(*d.longitudinal_acceleration_mps2, 1.5);
  EXPECT_DOUBLE_EQ(*d.lateral_acceleration_mps2, -0.5);
  EXPECT_NEAR(*d.steering_wheel_angle_deg, 0.02 * 15.0 * 180.0 / std::numbers::pi, 1e-4);
  EXPECT_TRUE(*d.brake_pedal);
  EXPECT_FALSE(*d.gas_pedal);
  EXPECT_EQ(*d.exterior_lights, facilities::lights::kLeftTurnSignal |
                                    facilities::lights::kRightTurnSignal |
                                    facilities::lights::kLowBeam);
  EXPECT_TRUE(*d.siren);
  EXPECT_FALSE(*d.light_bar);
  // Creeping backwards slower than the standstill threshold is not reversing.
  wire::VehicleState slow = state(3001, 200);
  slow.speed = -0.01f;
  vd.on_state(slow);
  EXPECT_FALSE(*got.back().reversing);
  EXPECT_NEAR(*got.back().speed_mps, 0.01, 1e-6);
}

}  // namespace
}  // namespace tb::host
