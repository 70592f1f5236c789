#include <gtest/gtest.h>

#include "common/scenario/loader.hpp"
#include "network-emulator/app/stations_config.hpp"
#include "network-emulator/app/tests/test_scenario.hpp"

namespace tb::emu {
namespace {

const scenario::Scenario& two() {
  static const auto s = scenario::parse(testing::kTwoStations, "two.json");
  return s;
}

std::string error_of(const std::string& json) {
  try {
    parse_stations(json, "st.json", two());
  } catch (const StationsConfigError& e) {
    return e.what();
  }
  return "no error";
}

TEST(StationsConfig, ReadsEveryField) {
  const auto st = parse_stations(R"({"stations": [
      {"station_id": 1001, "address": "10.1.0.2", "gnss_port": 11000, "can_port": 21000,
       "netns": "st1001", "can_interface": "vcan1"},
      {"station_id": 1002}]})",
                                 "st.json", two());
  ASSERT_EQ(st.size(), 2u);
  EXPECT_EQ(st[0].address, "10.1.0.2");
  EXPECT_EQ(st[0].gnss_port, 11000);
  EXPECT_EQ(st[0].can_port, 21000);
  EXPECT_EQ(st[0].netns, "st1001");
  EXPECT_EQ(st[0].can_interface, "vcan1");
  EXPECT_EQ(st[1].address, "127.0.0.1");
  EXPECT_EQ(st[1].gnss_port, kDefaultGnssPort);
}

TEST(StationsConfig, ErrorsNameFileFieldAndValue) {
  EXPECT_EQ(error_of(R"({"stations": [{"station_id": 7}]})"),
            "st.json: /stations/0/station_id: station 7 is not in scenario two.json");
  EXPECT_EQ(error_of(R"({"stations": [{"station_id": 1001}, {"station_id": 1001}]})"),
            "st.json: /stations/1/station_id: station 1001 listed twice");
  EXPECT_EQ(error_of(R"({"stations": [{"station_id": 1001, "address": "host.example"}]})"),
            "st.json: /stations/0/address: \"host.example\" is not an IP address");
  EXPECT_EQ(error_of(R"({"stations": [{"station_id": 1001, "gnss_port": 70000}]})"),
            "st.json: /stations/0/gnss_port: 70000 is not a port number (1..65535)");
  EXPECT_EQ(error_of(R"({"stations": [{"station_id": 1001, "gps_port": 1}]})"),
            "st.json: /stations/0/gps_port: unknown field");
  EXPECT_EQ(error_of(R"({"stations": [{"address": "1.2.3.4"}]})"),
            "st.json: /stations/0/station_id: required, an integer 0..4294967295");
  EXPECT_EQ(error_of(R"([1, 2])"),
            "st.json: /stations: expected an object with a \"stations\" array");
  EXPECT_NE(error_of("{oops").find("st.json: not valid JSON"), std::string::npos);
}

TEST(StationsConfig, DefaultsGiveEachStationItsOwnPorts) {
  const auto st = default_stations(two());
  ASSERT_EQ(st.size(), 2u);
  EXPECT_EQ(st[0].station_id, 1001u);
  EXPECT_EQ(st[1].gnss_port, kDefaultGnssPort + 1);
  EXPECT_EQ(st[1].can_port, kDefaultCanPort + 1);
}

}  // namespace
}  // namespace tb::emu
