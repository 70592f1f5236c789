#include "its-station/apps/mqtt/publisher.hpp"

#include "common/mqtt/mosquitto_client.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <vector>

namespace tb::its::apps::mqtt {
namespace {

using namespace std::chrono_literals;
using nlohmann::json;

struct Sent {
  std::string topic;
  json payload;
  tb::mqtt::Qos qos;
  bool retain;
};

class RecordingSink : public tb::mqtt::MqttSink {
 public:
  void publish(std::string_view topic, std::string payload, tb::mqtt::Qos qos,
               bool retain) override {
    sent.push_back(Sent{std::string(topic), json::parse(payload), qos, retain});
  }
  std::vector<Sent> sent;
};

class PublisherTest : public ::testing::Test {
 protected:
  clock::ManualClock clk;
  RecordingSink sink;
  StationPublisher pub{clk, sink, PublisherConfig{"its", 1001, 200ms}};

  ReceivedCam cam(std::uint32_t from) {
    ReceivedCam c;
    c.station_id = from;
    c.received_at = clk.wall_now();
    return c;
  }
};

TEST_F(PublisherTest, StateIsRetainedQos0UnderOwnPrefix) {
  StationState s;
  s.station_id = 1001;
  s.fix = GnssFix::k2D;
  pub.publish_state(s);
  ASSERT_EQ(sink.sent.size(), 1u);
  EXPECT_EQ(sink.sent[0].topic, "its/1001/state");
  EXPECT_EQ(sink.sent[0].qos, tb::mqtt::Qos::kAtMostOnce);
  EXPECT_TRUE(sink.sent[0].retain);
  EXPECT_EQ(sink.sent[0].payload["type"], "state");
  EXPECT_EQ(sink.sent[0].payload["source_uuid"], "station-1001");
  EXPECT_EQ(sink.sent[0].payload["timestamp"], unix_ms(clk.wall_now()));
  EXPECT_EQ(sink.sent[0].payload["message"]["gnss"]["fix"], "2d");
}

TEST_F(PublisherTest, CamsAreRateLimitedPerSource) {
  EXPECT_TRUE(pub.publish_cam(cam(7)));
  clk.advance(100ms);
  EXPECT_FALSE(pub.publish_cam(cam(7)));
  EXPECT_TRUE(pub.publish_cam(cam(8))) << "another source has its own budget";
  clk.advance(99ms);
  EXPECT_FALSE(pub.publish_cam(cam(7)));
  clk.advance(1ms);
  EXPECT_TRUE(pub.publish_cam(cam(7)));
  EXPECT_EQ(pub.cams_suppressed(), 2u);
  ASSERT_EQ(sink.sent.size(), 3u);
  EXPECT_EQ(sink.sent[0].topic, "its/1001/in/cam/7");
  EXPECT_EQ(sink.sent[1].topic, "its/1001/in/cam/8");
  EXPECT_EQ(sink.sent[0].qos, tb::mqtt::Qos::kAtMostOnce);
  EXPECT_FALSE(sink.sent[0].retain);
  EXPECT_EQ(sink.sent[0].payload["origin"], "remote");
}

TEST_F(PublisherTest, ZeroIntervalPublishesEveryCam) {
  StationPublisher all{clk, sink, PublisherConfig{"its", 1001, 0ms}};
  for (int i = 0; i < 5; ++i) {
    EXPECT_TRUE(all.publish_cam(cam(7)));
  }
  EXPECT_EQ(all.cams_suppressed(), 0u);
  ASSERT_EQ(sink.sent.size(), 5u);
  for (const auto& m : sink.sent) {
    EXPECT_EQ(m.topic, "its/1001/in/cam/7");
    EXPECT_EQ(m.payload["type"], "cam");
    EXPECT_EQ(m.payload["message"]["station_id"], 7);
  }
}

TEST_F(PublisherTest, WarningsAreQos1AndNotRetained) {
  LcrwWarning w;
  w.station_id = 1001;
  w.other_station_id = 1002;
  w.ttc_s = 2.5;
  pub.publish_warning(w);
  ASSERT_EQ(sink.sent.size(), 1u);
  EXPECT_EQ(sink.sent[0].topic, "its/1001/app/lcrw");
  EXPECT_EQ(sink.sent[0].qos, tb::mqtt::Qos::kAtLeastOnce);
  EXPECT_FALSE(sink.sent[0].retain);
  EXPECT_EQ(sink.sent[0].payload["type"], "lcrw_warning");
  EXPECT_DOUBLE_EQ(sink.sent[0].payload["message"]["ttc_s"].get<double>(), 2.5);
}

TEST_F(PublisherTest, SignalIsQos0AndRlvwQos1NeitherRetained) {
  signal::SignalStatus st;
  st.station_id = 1001;
  st.intersection_id = 5;
  st.on_lane = true;
  st.state = signal::MovementPhaseState::kStopAndRemain;
  pub.publish_signal(st);
  signal::RlvwWarning w;
  w.station_id = 1001;
  w.intersection_id = 5;
  pub.publish_rlvw(w);
  ASSERT_EQ(sink.sent.size(), 2u);
  EXPECT_EQ(sink.sent[0].topic, "its/1001/app/signal");
  EXPECT_EQ(sink.sent[0].qos, tb::mqtt::Qos::kAtMostOnce);
  EXPECT_FALSE(sink.sent[0].retain);
  EXPECT_EQ(sink.sent[0].payload["type"], "signal");
  EXPECT_EQ(sink.sent[0].payload["origin"], "on_board_application");
  EXPECT_EQ(sink.sent[0].payload["message"]["state"], "red");
  EXPECT_EQ(sink.sent[1].topic, "its/1001/app/rlvw");
  EXPECT_EQ(sink.sent[1].qos, tb::mqtt::Qos::kAtLeastOnce);
  EXPECT_FALSE(sink.sent[1].retain);
  EXPECT_EQ(sink.sent[1].payload["type"], "rlvw_warning");
  EXPECT_EQ(sink.sent[1].payload["message"]["intersection_id"], 5);
}

TEST_F(PublisherTest, DenmsByDirection) {
  DenmView d;
  d.action_id = {1002, 5};
  pub.publish_denm_received(d);
  d.action_id = {1001, 1};
  pub.publish_denm_sent(d);
  ASSERT_EQ(sink.sent.size(), 2u);
  EXPECT_EQ(sink.sent[0].topic, "its/1001/in/denm/1002");
  EXPECT_EQ(sink.sent[0].payload["origin"], "remote");
  EXPECT_EQ(sink.sent[1].topic, "its/1001/out/denm");
  EXPECT_EQ(sink.sent[1].payload["origin"], "self");
  EXPECT_EQ(sink.sent[1].qos, tb::mqtt::Qos::kAtLeastOnce);
}

}  // namespace
}  // namespace tb::its::apps::mqtt

namespace tb::its::apps::mqtt {
namespace {

TEST(MosquittoClientPrefix, RefusesTopicsOutsideTheStationPrefix) {
  clock::ManualClock clk;
  tb::mqtt::ClientConfig cfg;
  cfg.publish_prefix = "its/1001/";
  tb::mqtt::MosquittoClient client(clk, cfg);  // never started: no broker needed
  client.publish("its/1002/app/lcrw", "{}", tb::mqtt::Qos::kAtLeastOnce, false);
  client.publish("its/1001x/state", "{}", tb::mqtt::Qos::kAtMostOnce, false);
  EXPECT_EQ(client.refused(), 2u);
  EXPECT_EQ(client.pending(), 0u);
  client.publish("its/1001/app/lcrw", "{}", tb::mqtt::Qos::kAtLeastOnce, false);
  EXPECT_EQ(client.refused(), 2u);
  EXPECT_EQ(client.pending(), 1u) << "queued until a broker is there";
}

TEST(MosquittoClientPrefix, StatusTopicMustBeUnderThePrefix) {
  clock::ManualClock clk;
  tb::mqtt::ClientConfig cfg;
  cfg.publish_prefix = "its/1001/";
  cfg.status_topic = "its/1002/status";
  EXPECT_THROW(tb::mqtt::MosquittoClient(clk, cfg), tb::mqtt::MqttError);
}

}  // namespace
}  // namespace tb::its::apps::mqtt

namespace tb::its::apps::mqtt {
namespace {

TEST_F(PublisherTest, TracesPublishedCamsAndWarnings) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("hmi-mqtt-trace-" + std::to_string(::getpid()) + ".jsonl");
  {
    trace::Tracer tracer(path.string(), "its-station");
    pub.set_tracer(&tracer);
    auto c = cam(7);
    c.generation_delta_time = 4242;
    pub.publish_cam(c);
    pub.publish_cam(c);  // rate-limited: not published, not traced
    LcrwWarning w;
    w.station_id = 1001;
    w.other_station_id = 7;
    w.other_state_time = clock::WallTime{std::chrono::milliseconds{kItsEpochUnixMs + 70000}};
    w.own_state_time = clock::WallTime{std::chrono::milliseconds{kItsEpochUnixMs + 70040}};
    pub.publish_warning(w);
    pub.set_tracer(nullptr);
    tracer.flush();
  }
  std::ifstream in(path);
  std::vector<json> r;
  for (std::string line; std::getline(in, line);) {
    r.push_back(json::parse(line));
  }
  std::filesystem::remove(path);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[0]["ev"], "its.mqtt");
  EXPECT_EQ(r[0]["station"], 1001);
  EXPECT_EQ(r[0]["topic"], "its/1001/in/cam/7");
  EXPECT_EQ(r[0]["from"], 7);
  EXPECT_EQ(r[0]["gdt"], 4242);
  EXPECT_EQ(r[1]["topic"], "its/1001/app/lcrw");
  EXPECT_EQ(r[1]["gdt"], 70000 - 65536);
  EXPECT_EQ(r[1]["own_ms"], kItsEpochUnixMs + 70040);
  EXPECT_EQ(r[1]["event"], "raised");
}

}  // namespace
}  // namespace tb::its::apps::mqtt

namespace tb::its::apps::mqtt {
namespace {

TEST_F(PublisherTest, TracesSignalMessagesAndRlvwEvents) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("signal-mqtt-trace-" + std::to_string(::getpid()) + ".jsonl");
  {
    trace::Tracer tracer(path.string(), "its-station");
    pub.set_tracer(&tracer);
    signal::SignalStatus s;
    s.station_id = 1001;
    s.intersection_id = 5;
    s.on_lane = true;
    s.lane_id = 2;
    s.state = signal::MovementPhaseState::kProtectedClearance;
    s.time = clock::WallTime{std::chrono::milliseconds{1'763'770'000'100}};
    pub.publish_signal(s);
    s.on_lane = false;
    pub.publish_signal(s);
    signal::RlvwWarning w;
    w.intersection_id = 5;
    w.lane_id = 2;
    w.updated_at = clock::WallTime{std::chrono::milliseconds{1'763'770'000'200}};
    pub.publish_rlvw(w);
    pub.set_tracer(nullptr);
    tracer.flush();
  }
  std::ifstream in(path);
  std::vector<json> records;
  for (std::string line; std::getline(in, line);) {
    records.push_back(json::parse(line));
  }
  std::filesystem::remove(path);
  ASSERT_EQ(records.size(), 3u);
  EXPECT_EQ(records[0]["ev"], "its.mqtt");
  EXPECT_EQ(records[0]["topic"], "its/1001/app/signal");
  EXPECT_EQ(records[0]["intersection"], 5);
  EXPECT_EQ(records[0]["lane"], 2);
  EXPECT_EQ(records[0]["state"], 8);
  EXPECT_EQ(records[0]["own_ms"], 1'763'770'000'100);
  EXPECT_EQ(records[1]["lane"], -1) << "leaving the lane";
  EXPECT_EQ(records[2]["topic"], "its/1001/app/rlvw");
  EXPECT_EQ(records[2]["event"], "raised");
  EXPECT_EQ(records[2]["own_ms"], 1'763'770'000'200);
}

}  // namespace
}  // namespace tb::its::apps::mqtt
