#include "its-station/station/time_synced_link.hpp"

#include <array>

#include <gtest/gtest.h>

#include "its-station/link/test_link.hpp"

namespace tb::its::station {
namespace {

using clock::GnssDisciplinedRuntime;
using clock::WallTime;

// The host believes it is late 2026; the world (a pinned scenario) runs in mid 2025.
const WallTime kHostStart{std::chrono::seconds{1'795'000'000}};
const WallTime kWorldStart{std::chrono::seconds{1'748'854'800}};  // 2025-06-02T09:00:00Z

// The e2e signed three-vehicle case: a station that had no fix yet judged its neighbours' CAMs
// on the host's clock, seconds ahead of the world's, and refused them as out of the window.
TEST(TimeSyncedLink, TakesFramesInOnlyOnceTheClockHasAFix) {
  clock::ManualRuntime host(kHostStart);
  GnssDisciplinedRuntime its(host);
  link::TestLink inner(link::MacAddress{2, 0, 0, 0, 0, 1});
  TimeSyncedLink synced(inner, its);
  int delivered = 0;
  synced.set_receive_handler([&](const link::ReceivedFrame&) { ++delivered; });
  const std::array<std::uint8_t, 3> payload{1, 2, 3};
  inner.inject(link::MacAddress{2, 0, 0, 0, 0, 2}, link::kBroadcastMac, 0x8947, payload,
               host.wall_now());
  EXPECT_EQ(delivered, 0);
  EXPECT_EQ(synced.dropped_before_sync(), 1u);
  its.on_fix(kWorldStart);
  inner.inject(link::MacAddress{2, 0, 0, 0, 0, 2}, link::kBroadcastMac, 0x8947, payload,
               host.wall_now());
  EXPECT_EQ(delivered, 1);
  EXPECT_EQ(synced.dropped_before_sync(), 1u);
  // Sending is not gated here: before a fix the station has nothing to send.
  EXPECT_FALSE(synced.send(link::kBroadcastMac, 0x8947, payload));
  EXPECT_EQ(inner.sent().size(), 1u);
}

}  // namespace
}  // namespace tb::its::station
