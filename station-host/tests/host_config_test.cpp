#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "station-host/app/host_config.hpp"

namespace tb::host {
namespace {

std::string error_of(auto&& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(HostConfig, StatesUrl) {
  const UdpEndpoint e = parse_states_url("udp://0.0.0.0:4710");
  EXPECT_EQ(e.address, "0.0.0.0");
  EXPECT_EQ(e.port, 4710);
  EXPECT_EQ(parse_states_url("udp://[::1]:9").address, "::1");
  for (const char* bad :
       {"tcp://0.0.0.0:4710", "udp://0.0.0.0", "udp://host:4710", "udp://0.0.0.0:0",
        "udp://0.0.0.0:70000", "udp://0.0.0.0:47x", "udp://:1"})
    EXPECT_NE(error_of([&] { parse_states_url(bad); }).find(std::string("--states '") + bad),
              std::string::npos)
        << bad;
}

TEST(HostConfig, StationList) {
  EXPECT_EQ(parse_station_list("3004,3007,12"), (std::vector<std::uint32_t>{3004, 3007, 12}));
  EXPECT_EQ(error_of([] { parse_station_list("3004,,3007"); }),
            "--stations '3004,,3007': '' is not a station id");
  EXPECT_EQ(error_of([] { parse_station_list("3004,x"); }),
            "--stations '3004,x': 'x' is not a station id");
  EXPECT_EQ(error_of([] { parse_station_list("1,1"); }),
            "--stations '1,1': station 1 is listed twice");
  EXPECT_NE(error_of([] { parse_station_list(""); }), "");
}

TEST(HostConfig, OnlyPooledVehiclesOfTheScenario) {
  scenario::Scenario s;
  s.source = "s.json";
  scenario::Vehicle full;
  full.id = "ego";
  full.station_id = 1;
  scenario::Vehicle pooled = full;
  pooled.id = "bg";
  pooled.station_id = 2;
  pooled.station_kind = scenario::StationKind::kPooled;
  s.vehicles = {full, pooled};
  const std::vector<std::uint32_t> ok{2};
  ASSERT_EQ(pooled_vehicles(s, ok).size(), 1u);
  EXPECT_EQ(pooled_vehicles(s, ok)[0]->id, "bg");
  const std::vector<std::uint32_t> unknown{2, 7};
  EXPECT_EQ(error_of([&] { pooled_vehicles(s, unknown); }),
            "--stations: 7 is not a station of scenario s.json");
  const std::vector<std::uint32_t> not_pooled{1};
  EXPECT_NE(error_of([&] {
              pooled_vehicles(s, not_pooled);
            }).find("station 1 (vehicle 'ego') is not pooled in scenario s.json"),
            std::string::npos);
}

TEST(HostConfig, ForwardingAsRadioMediumResolvesIt) {
  EXPECT_EQ(resolve_forwarding("auto", ""), Forwarding::kKernel);
  EXPECT_EQ(resolve_forwarding("auto", "the range channel decides"), Forwarding::kUser);
  EXPECT_EQ(resolve_forwarding("user", ""), Forwarding::kUser);
  EXPECT_EQ(resolve_forwarding("kernel", ""), Forwarding::kKernel);
  EXPECT_NE(error_of([] { resolve_forwarding("kernel", "the range channel decides"); }), "");
  EXPECT_EQ(error_of([] { resolve_forwarding("bridge", ""); }),
            "--forwarding 'bridge': expected auto, kernel or user");
}

TEST(HostConfig, PkiDirectoryPerStation) {
  const auto dir = std::filesystem::path(::testing::TempDir()) / "host_config_pki";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir / "3004");
  EXPECT_EQ(station_pki_dir(dir, 3004), dir / "3004");
  EXPECT_NE(error_of([&] { station_pki_dir(dir, 3005); }).find("for station 3005"),
            std::string::npos);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace tb::host
