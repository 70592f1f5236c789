#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "common/scenario/loader.hpp"
#include "sim-server/physics/world.hpp"

namespace tb::server::physics {
namespace {

/// A run: the scenario file's world, stepped with controls from a seeded generator.
std::vector<std::uint8_t> run(const scenario::Scenario& sc, std::uint32_t seed, int steps) {
  World w(sc, WorldOptions{.step_s = 1.0 / sc.rates.physics_hz});
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<std::uint8_t> out;
  for (int i = 0; i < steps; ++i) {
    if (i % 25 == 0) {
      for (std::size_t v = 0; v < w.size(); ++v) {
        const float a = u(rng);
        w.set_controls(
            v, {a > 0.3f ? a : 0.0f, a < 0.2f ? 1.0f - a : 0.0f, u(rng) * 2 - 1, false, false}, 0);
      }
    }
    w.step(0);
    for (const auto& s : w.states()) {
      const auto b = wire::encode(s);
      out.insert(out.end(), b.begin(), b.end());
    }
  }
  return out;
}

TEST(Determinism, SameScenarioAndInputsGiveBitIdenticalStates) {
  const auto sc = scenario::load_file("sim-server/tests/scenarios/three-cars.json");
  const auto a = run(sc, 7, 1500);
  const auto b = run(sc, 7, 1500);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size()), 0);
  // And the comparison can see a difference: other inputs, other states.
  const auto c = run(sc, 8, 1500);
  EXPECT_NE(std::memcmp(a.data(), c.data(), a.size()), 0);
}

}  // namespace
}  // namespace tb::server::physics

namespace tb::server::physics {
namespace {

TEST(WorldStates, EveryStateDecodes) {
  // Every state must pass the wire decoder's checks (finite numbers, controls in range), from
  // the first one on, before any wheel has touched the ground.
  const auto sc = scenario::load_file("sim-server/tests/scenarios/three-cars.json");
  World w(sc);
  auto all_decode = [&](const char* when) {
    for (const auto& s : w.states()) {
      const auto d = wire::decode(wire::encode(s));
      if (!d) {
        ADD_FAILURE() << when << " tick " << w.tick() << " station " << s.station_id << ": "
                      << wire::to_string(d.error());
        return false;
      }
    }
    return true;
  };
  ASSERT_TRUE(all_decode("spawn"));
  for (int i = 0; i < 500; ++i) {
    w.set_controls(i % 3, {0.7f, 0.0f, (i % 50) / 50.0f - 0.5f, false, false}, 0);
    w.step();
    ASSERT_TRUE(all_decode("step"));
  }
}

}  // namespace
}  // namespace tb::server::physics
