#include "network-emulator/radio/placement.hpp"

#include <gtest/gtest.h>

namespace tb::emu::radio {
namespace {

// The refusal must name the file, the field and the offending value.
void expect_refused(const std::string& text, std::initializer_list<std::string> needles) {
  try {
    (void)parse_placement(text, "swarm/placement.json");
    FAIL() << "accepted: " << text;
  } catch (const PlacementError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("swarm/placement.json"), std::string::npos) << msg;
    for (const auto& n : needles)
      EXPECT_NE(msg.find(n), std::string::npos) << "\"" << n << "\" not in: " << msg;
  }
}

TEST(PlacementTest, ReadsTheContractsExample) {
  const auto p = parse_placement(R"({"nodes": [
     {"name": "tb-node1", "medium": "emulator-tb-node1:4730", "stations": [1001, 1003, 5001],
      "pooled": [2001, 2003], "station_hosts": 1},
     {"name": "tb-node2", "medium": "10.0.0.2:4731", "stations": [1002],
      "pooled": [2002], "station_hosts": 1}]})",
                                 "p.json");
  ASSERT_EQ(p.nodes.size(), 2u);
  EXPECT_EQ(p.nodes[0].name, "tb-node1");
  EXPECT_EQ(p.nodes[0].medium_host, "emulator-tb-node1");
  EXPECT_EQ(p.nodes[0].medium_port, 4730);
  EXPECT_EQ(p.nodes[0].stations, (std::vector<StationId>{1001, 1003, 5001}));
  EXPECT_EQ(p.nodes[0].pooled, (std::vector<StationId>{2001, 2003}));
  EXPECT_EQ(p.nodes[1].medium_host, "10.0.0.2");
  EXPECT_EQ(p.nodes[1].medium_port, 4731);
  EXPECT_EQ(p.node_of(2002)->name, "tb-node2");
  EXPECT_EQ(p.node_of(5001)->name, "tb-node1");
  EXPECT_EQ(p.node_of(9999), nullptr);
}

TEST(PlacementTest, AStationOnTwoNodesIsRefusedNamingItAndBothNodes) {
  expect_refused(R"({"nodes": [{"name": "a", "medium": "a:1", "stations": [7, 8]},
                               {"name": "b", "medium": "b:1", "stations": [9], "pooled": [8],
                                "station_hosts": 1}]})",
                 {"nodes[1].pooled", "station 8", "a (stations)", "b (pooled)"});
}

TEST(PlacementTest, BadFieldsAreRefusedNamingFieldAndValue) {
  expect_refused("{\"nodes\": [", {"not JSON"});
  expect_refused(R"({"node": []})", {"nodes", "missing"});
  expect_refused(R"({"nodes": []})", {"nodes", "non-empty"});
  expect_refused(R"({"nodes": [{"medium": "a:1"}]})", {"nodes[0].name", "missing"});
  expect_refused(R"({"nodes": [{"name": "a", "stations": [1]}]})", {"nodes[0].medium", "missing"});
  expect_refused(R"({"nodes": [{"name": "a", "medium": "emulator-a"}]})",
                 {"nodes[0].medium", "\"emulator-a\"", "HOST:PORT"});
  expect_refused(R"({"nodes": [{"name": "a", "medium": "emulator-a:70000"}]})",
                 {"nodes[0].medium", "70000"});
  expect_refused(R"({"nodes": [{"name": "a", "medium": "a:1", "stations": [1, "x"]}]})",
                 {"nodes[0].stations[1]", "\"x\""});
  expect_refused(R"({"nodes": [{"name": "a", "medium": "a:1", "stations": [-3]}]})",
                 {"nodes[0].stations[0]", "-3"});
  expect_refused(R"({"nodes": [{"name": "a", "medium": "a:1"}, {"name": "a", "medium": "b:1"}]})",
                 {"nodes[1].name", "\"a\"", "twice"});
  expect_refused(R"({"nodes": [{"name": "a", "medium": "a:1", "pooled": [4]}]})",
                 {"nodes[0].station_hosts", "1 pooled"});
}

TEST(PlacementTest, AMissingFileIsNamed) {
  try {
    (void)load_placement("/nonexistent/placement.json");
    FAIL();
  } catch (const PlacementError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/placement.json"), std::string::npos);
  }
}

TEST(PlacementTest, HostPort) {
  EXPECT_EQ(parse_host_port("[::1]:4730")->host, "::1");
  EXPECT_EQ(parse_host_port("h:1")->port, 1);
  EXPECT_FALSE(parse_host_port("::1:4730"));
  EXPECT_FALSE(parse_host_port(":4730"));
  EXPECT_FALSE(parse_host_port("h:"));
  EXPECT_FALSE(parse_host_port("h:4x"));
}

}  // namespace
}  // namespace tb::emu::radio
