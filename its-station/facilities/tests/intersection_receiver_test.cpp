// MAPEM and SPATEM into the LDM's intersection store: messages built here and encoded with the
// codec, the clock moved by hand.
#include "its-station/facilities/intersection_receiver.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <vector>

#include "common/clock/clock.hpp"

namespace tb::its::facilities {
namespace {

namespace m = messages;
using namespace std::chrono_literals;

std::vector<std::uint8_t> mapem_bytes(m::IntersectionID id, m::MsgCount revision) {
  auto mapem = std::make_unique<m::Mapem>();
  auto& g = mapem->map.intersections.emplace().emplace_back();
  g.id.id = id;
  g.revision = revision;
  g.refPoint.lat = 481371540;
  g.refPoint.long_ = 115761240;
  auto& lane = g.laneSet.emplace_back();
  lane.laneID = 1;
  lane.laneAttributes.directionalUse = m::lane_direction::kIngressPath;
  m::NodeSetXY nodes;
  nodes.push_back({m::node_xy(-150, -1000), std::nullopt});
  nodes.push_back({m::node_xy(0, -2000), std::nullopt});
  lane.nodeList = nodes;
  lane.connectsTo.emplace().push_back(
      {{2, std::nullopt}, std::nullopt, std::uint8_t{1}, std::nullopt, std::nullopt});
  return *m::encode(*mapem);
}

std::vector<std::uint8_t> spatem_bytes(m::IntersectionID id, m::MovementPhaseState state) {
  auto spatem = std::make_unique<m::Spatem>();
  auto& is = spatem->spat.intersections.emplace_back();
  is.id.id = id;
  auto& ms = is.states.emplace_back();
  ms.signalGroup = 1;
  ms.state_time_speed.emplace_back().eventState = state;
  return *m::encode(*spatem);
}

struct IntersectionReceiverTest : ::testing::Test {
  clock::ManualClock clock;
  IntersectionStore store{clock};
  IntersectionReceiver rx{store};
  std::vector<MapOutcome> map_outcomes;
  std::vector<m::MovementPhaseState> spat_states;
  IntersectionReceiverTest() {
    rx.on_map([this](const IntersectionEntry& e, MapOutcome o) {
      EXPECT_NE(e.map, nullptr);
      map_outcomes.push_back(o);
    });
    rx.on_spat([this](const IntersectionEntry& e) {
      spat_states.push_back(e.spat->states[0].state_time_speed[0].eventState);
    });
  }
};

TEST_F(IntersectionReceiverTest, MapRevisionsReplaceTheSameOneRefreshes) {
  rx.receive_mapem(mapem_bytes(100, 3));
  const IntersectionEntry* e = store.find(100);
  ASSERT_NE(e, nullptr);
  ASSERT_NE(e->map, nullptr);
  EXPECT_EQ(e->map->revision, 3);
  EXPECT_EQ(e->map->laneSet[0].laneID, 1);
  const auto* held = e->map.get();
  rx.receive_mapem(mapem_bytes(100, 3));
  EXPECT_EQ(store.find(100)->map.get(), held);  // not copied again
  rx.receive_mapem(mapem_bytes(100, 4));
  EXPECT_EQ(store.find(100)->map->revision, 4);
  rx.receive_mapem(mapem_bytes(101, 0));
  EXPECT_EQ(store.maps(), 2u);
  EXPECT_EQ(map_outcomes, (std::vector<MapOutcome>{MapOutcome::kNew, MapOutcome::kRefreshed,
                                                   MapOutcome::kNewRevision, MapOutcome::kNew}));
  EXPECT_EQ(rx.counters().mapem_received, 4u);
}

TEST_F(IntersectionReceiverTest, ValidityEndsMapAfter30sAndSpatAfter2s) {
  rx.receive_mapem(mapem_bytes(100, 3));
  rx.receive_spatem(spatem_bytes(100, m::MovementPhaseState::stop_And_Remain));
  ASSERT_NE(store.find(100)->spat, nullptr);
  clock.advance(2s);
  store.expire();
  EXPECT_NE(store.find(100)->spat, nullptr);  // at 2 s still valid
  clock.advance(1ms);
  store.expire();
  EXPECT_EQ(store.find(100)->spat, nullptr);
  EXPECT_NE(store.find(100)->map, nullptr);
  clock.advance(25s);
  rx.receive_mapem(mapem_bytes(100, 3));  // heard again: valid 30 s from now
  clock.advance(30s);
  store.expire();
  ASSERT_NE(store.find(100), nullptr);
  clock.advance(1ms);
  store.expire();
  EXPECT_EQ(store.find(100), nullptr);
  EXPECT_TRUE(store.entries().empty());
}

TEST_F(IntersectionReceiverTest, LatestSpatWins) {
  rx.receive_spatem(spatem_bytes(7, m::MovementPhaseState::protected_Movement_Allowed));
  rx.receive_spatem(spatem_bytes(7, m::MovementPhaseState::protected_clearance));
  EXPECT_EQ(store.find(7)->spat->states[0].state_time_speed[0].eventState,
            m::MovementPhaseState::protected_clearance);
  EXPECT_EQ(spat_states,
            (std::vector<m::MovementPhaseState>{m::MovementPhaseState::protected_Movement_Allowed,
                                                m::MovementPhaseState::protected_clearance}));
  EXPECT_EQ(store.find(7)->map, nullptr);
  EXPECT_EQ(rx.counters().spatem_received, 2u);
}

// Every truncation and a CAM on the wrong port: counted, nothing stored, never a misread.
TEST_F(IntersectionReceiverTest, UndecodableMessagesAreCountedAndDropped) {
  const auto map = mapem_bytes(100, 3);
  const auto spat = spatem_bytes(100, m::MovementPhaseState::stop_And_Remain);
  for (std::size_t n = 0; n < map.size(); ++n)
    rx.receive_mapem(std::span(map).first(n));
  for (std::size_t n = 0; n < spat.size(); ++n)
    rx.receive_spatem(std::span(spat).first(n));
  rx.receive_spatem(map);  // a MAPEM on the SPATEM port: messageID 5, not 4
  rx.receive_mapem(spat);
  EXPECT_EQ(rx.counters().mapem_decode_errors, map.size() + 1);
  EXPECT_EQ(rx.counters().spatem_decode_errors, spat.size() + 1);
  EXPECT_EQ(rx.counters().mapem_received, 0u);
  EXPECT_EQ(rx.counters().spatem_received, 0u);
  EXPECT_TRUE(store.entries().empty());
  EXPECT_TRUE(map_outcomes.empty());
}

}  // namespace
}  // namespace tb::its::facilities
