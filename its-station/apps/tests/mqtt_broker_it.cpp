// Integration: the project's broker configuration (docker/mosquitto) on a real Mosquitto, and
// the station's MQTT client against it. Each test starts its own broker on free loopback ports.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <mosquitto.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "common/mqtt/mosquitto_client.hpp"
#include "common/mqtt/tests/test_broker.hpp"
#include "its-station/apps/mqtt/publisher.hpp"

namespace tb::its::apps::mqtt {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using nlohmann::json;
using tb::mqtt::testing::Broker;
using tb::mqtt::testing::repo_root;
using tb::mqtt::testing::wait_until;

/// A plain libmosquitto client for the test's side: subscribes (and resubscribes after a
/// reconnect) and records what arrives; publishes with MQTT v5 to see the broker's reason code.
class Probe {
 public:
  Probe(const std::string& id, const std::string& user, const std::string& pass, int port,
        bool persistent_session = false)
      : port_(port) {
    mosquitto_lib_init();
    m_ = mosquitto_new(id.c_str(), !persistent_session, this);
    // MQTT v5 for the reason codes of refused publishes; v3.1.1 for a persistent session,
    // which v5 would end at disconnection unless given a session expiry interval.
    mosquitto_int_option(m_, MOSQ_OPT_PROTOCOL_VERSION,
                         persistent_session ? MQTT_PROTOCOL_V311 : MQTT_PROTOCOL_V5);
    if (!user.empty()) {
      mosquitto_username_pw_set(m_, user.c_str(), pass.c_str());
    }
    mosquitto_reconnect_delay_set(m_, 1, 1, false);
    mosquitto_connect_v5_callback_set(
        m_, [](mosquitto*, void* p, int rc, int, const mosquitto_property*) {
          auto* self = static_cast<Probe*>(p);
          std::lock_guard l(self->mu_);
          self->connack_ = rc;
          if (rc == 0) {
            for (const auto& t : self->subs_) {
              mosquitto_subscribe(self->m_, nullptr, t.c_str(), 1);
            }
          }
        });
    mosquitto_subscribe_callback_set(m_, [](mosquitto*, void* p, int, int, const int*) {
      auto* self = static_cast<Probe*>(p);
      std::lock_guard l(self->mu_);
      ++self->subacks_;
    });
    mosquitto_message_callback_set(m_, [](mosquitto*, void* p, const mosquitto_message* msg) {
      auto* self = static_cast<Probe*>(p);
      std::lock_guard l(self->mu_);
      self->got_.push_back({msg->topic, std::string(static_cast<const char*>(msg->payload),
                                                    static_cast<std::size_t>(msg->payloadlen))});
    });
    mosquitto_publish_v5_callback_set(
        m_, [](mosquitto*, void* p, int mid, int reason, const mosquitto_property*) {
          auto* self = static_cast<Probe*>(p);
          std::lock_guard l(self->mu_);
          self->puback_[mid] = reason;
        });
  }
  ~Probe() {
    mosquitto_disconnect(m_);
    mosquitto_loop_stop(m_, true);
    mosquitto_destroy(m_);
  }
  void subscribe_on_connect(const std::string& topic) { subs_.push_back(topic); }
  /// Connects and waits for the CONNACK (and the SUBACKs); returns the CONNACK reason code.
  int connect() {
    mosquitto_connect_async(m_, "127.0.0.1", port_, 10);
    mosquitto_loop_start(m_);
    wait_until([&] { return connack() >= 0; }, 5s);
    if (connack() == 0) {
      wait_until([&] { return subacks() >= static_cast<int>(subs_.size()); }, 5s);
    }
    return connack();
  }
  int connack() {
    std::lock_guard l(mu_);
    return connack_;
  }
  int subacks() {
    std::lock_guard l(mu_);
    return subacks_;
  }
  /// Publishes QoS 1 and returns the PUBACK reason code (-1 on timeout).
  int publish_and_wait(const std::string& topic, const std::string& payload) {
    int mid = 0;
    if (mosquitto_publish_v5(m_, &mid, topic.c_str(), static_cast<int>(payload.size()),
                             payload.data(), 1, false, nullptr) != MOSQ_ERR_SUCCESS) {
      return -1;
    }
    wait_until(
        [&] {
          std::lock_guard l(mu_);
          return puback_.count(mid) > 0;
        },
        5s);
    std::lock_guard l(mu_);
    return puback_.count(mid) ? puback_[mid] : -1;
  }
  std::vector<std::pair<std::string, std::string>> messages() {
    std::lock_guard l(mu_);
    return got_;
  }
  bool wait_messages(std::size_t n, std::chrono::milliseconds timeout) {
    return wait_until([&] { return messages().size() >= n; }, timeout);
  }

 private:
  mosquitto* m_ = nullptr;
  int port_;
  std::mutex mu_;
  int connack_ = -1;
  int subacks_ = 0;
  std::vector<std::string> subs_;
  std::vector<std::pair<std::string, std::string>> got_;
  std::map<int, int> puback_;
};

/// Runs gen-broker-config on a scenario text; returns its exit status and what it printed.
std::pair<int, std::string> generate(const std::string& scenario_text, const fs::path& dir) {
  fs::create_directories(dir);
  std::ofstream(dir / "scenario.json") << scenario_text;
  const std::string cmd = (repo_root() / "docker/mosquitto/gen-broker-config").string() +
                          " --scenario " + (dir / "scenario.json").string() + " --out " +
                          (dir / "out").string() + " > " + (dir / "log").string() + " 2>&1";
  const int status = std::system(cmd.c_str());
  std::ifstream f(dir / "log");
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1,
          std::string(std::istreambuf_iterator<char>(f), {})};
}

TEST(BrokerGenerator, WritesAclForTheScenarioStations) {
  const fs::path dir = fs::temp_directory_path() / ("hmi-gen-" + std::to_string(::getpid()));
  const auto [rc, out] =
      generate(R"({"vehicles": [{"station_id": 7}, {"station_id": 4294967295}]})", dir);
  EXPECT_EQ(rc, 0) << out;
  std::ifstream acl(dir / "out/acl");
  const std::string text(std::istreambuf_iterator<char>(acl), {});
  EXPECT_NE(text.find("user station-7\ntopic write its/7/#"), std::string::npos) << text;
  EXPECT_NE(text.find("user station-4294967295\ntopic write its/4294967295/#"), std::string::npos);
  EXPECT_NE(text.find("user hmi\ntopic read its/#"), std::string::npos);
  EXPECT_TRUE(fs::exists(dir / "out/stations/7.password"));
  EXPECT_EQ(fs::status(dir / "out/credentials.json").permissions() & fs::perms::others_read,
            fs::perms::none);
  fs::remove_all(dir);
}

TEST(BrokerGenerator, BadScenariosExitWithTwoAndNameTheField) {
  const fs::path dir = fs::temp_directory_path() / ("hmi-gen-bad-" + std::to_string(::getpid()));
  auto [rc, out] = generate(R"({"vehicles": [{"station_id": 1}, {"station_id": "x"}]})", dir);
  EXPECT_EQ(rc, 2);
  EXPECT_NE(out.find("/vehicles/1/station_id"), std::string::npos) << out;
  EXPECT_NE(out.find("\"x\""), std::string::npos) << out;
  std::tie(rc, out) = generate(R"({"vehicles": [{"station_id": 1}, {"station_id": 1}]})", dir);
  EXPECT_EQ(rc, 2);
  EXPECT_NE(out.find("duplicate station id(s): 1"), std::string::npos) << out;
  std::tie(rc, out) = generate("{not json", dir);
  EXPECT_EQ(rc, 2);
  EXPECT_NE(out.find("not JSON"), std::string::npos) << out;
  std::tie(rc, out) = generate(R"({"vehicles": []})", dir);
  EXPECT_EQ(rc, 2);
  EXPECT_NE(out.find("/vehicles"), std::string::npos) << out;
  fs::remove_all(dir);
}

constexpr int kReasonSuccess = 0;
constexpr int kReasonNotAuthorized = 135;  // MQTT v5 0x87

TEST(BrokerConfig, StationWritesOnlyUnderItsOwnPrefix) {
  Broker broker("1001,1002");
  ASSERT_TRUE(broker.configured());
  ASSERT_TRUE(broker.start()) << broker.log();
  Probe hmi("hmi-probe", "hmi", "hmi", broker.port());
  hmi.subscribe_on_connect("its/#");
  ASSERT_EQ(hmi.connect(), kReasonSuccess);

  Probe station("station-1001", "station-1001", broker.password(1001), broker.port());
  ASSERT_EQ(station.connect(), kReasonSuccess);
  EXPECT_EQ(station.publish_and_wait("its/1002/app/lcrw", "forged"), kReasonNotAuthorized);
  EXPECT_EQ(station.publish_and_wait("its/1001x/state", "forged"), kReasonNotAuthorized);
  EXPECT_EQ(station.publish_and_wait("elsewhere", "forged"), kReasonNotAuthorized);
  EXPECT_EQ(station.publish_and_wait("its/1001/state", "mine"), kReasonSuccess);

  ASSERT_TRUE(hmi.wait_messages(1, 3s));
  std::this_thread::sleep_for(200ms);  // room for a forged message to (wrongly) arrive
  const auto got = hmi.messages();
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].first, "its/1001/state");
  EXPECT_EQ(got[0].second, "mine");
}

TEST(BrokerConfig, ReadersPublishOnlyHmiTraceRecords) {
  Broker broker("1001");
  ASSERT_TRUE(broker.configured());
  ASSERT_TRUE(broker.start()) << broker.log();
  Probe collector("collector-probe", "hmi", "hmi", broker.port());
  collector.subscribe_on_connect("its/#");
  ASSERT_EQ(collector.connect(), kReasonSuccess);
  Probe hmi("hmi-probe", "hmi", "hmi", broker.port());
  ASSERT_EQ(hmi.connect(), kReasonSuccess);
  EXPECT_EQ(hmi.publish_and_wait("its/1001/app/lcrw", "forged"), kReasonNotAuthorized);
  EXPECT_EQ(hmi.publish_and_wait("its/1001/hmi/trace/x", "deeper"), kReasonNotAuthorized);
  EXPECT_EQ(hmi.publish_and_wait("its/1001/hmi", "beside"), kReasonNotAuthorized);
  // The HMI's receipts of LCRW warnings (hmi/src/trace.js), read by the launcher's collector.
  EXPECT_NE(hmi.publish_and_wait("its/1001/hmi/trace", "{}"), kReasonNotAuthorized);
  ASSERT_TRUE(collector.wait_messages(1, 3s)) << broker.log();
  const auto got = collector.messages();
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].first, "its/1001/hmi/trace");
}

TEST(BrokerConfig, RefusesAnonymousAndWrongPasswords) {
  Broker broker("1001");
  ASSERT_TRUE(broker.configured());
  ASSERT_TRUE(broker.start()) << broker.log();
  Probe anon("anon-probe", "", "", broker.port());
  EXPECT_EQ(anon.connect(), kReasonNotAuthorized);
  Probe wrong("wrong-probe", "station-1001", "not-the-password", broker.port());
  EXPECT_NE(wrong.connect(), kReasonSuccess);
  // The station client reports the refusal (MQTT 3.1.1 CONNACK 5, not authorised).
  clock::SystemClock clk;
  tb::mqtt::ClientConfig anon_cfg;
  anon_cfg.port = broker.port();
  anon_cfg.client_id = "anon-station";
  tb::mqtt::MosquittoClient client(clk, anon_cfg);
  client.start();
  EXPECT_TRUE(wait_until([&] { return client.last_connack() >= 0; }, 5s));
  EXPECT_EQ(client.last_connack(), 5);
  EXPECT_FALSE(client.connected());
}

LcrwWarning warning(std::uint32_t other, double ttc) {
  LcrwWarning w;
  w.station_id = 1001;
  w.other_station_id = other;
  w.ttc_s = ttc;
  return w;
}

tb::mqtt::ClientConfig station_config(const Broker& b, std::size_t capacity = 100) {
  tb::mqtt::ClientConfig c;
  c.port = b.port();
  c.client_id = "station-1001";
  c.username = "station-1001";
  c.password = b.password(1001);
  c.reconnect_min_s = 1;
  c.reconnect_max_s = 2;
  c.queue_capacity = capacity;
  c.status_topic = "its/1001/status";
  c.publish_prefix = "its/1001/";
  return c;
}

std::vector<json> lcrw_payloads(Probe& p) {
  std::vector<json> out;
  for (const auto& [topic, payload] : p.messages()) {
    if (topic == "its/1001/app/lcrw") {
      out.push_back(json::parse(payload));
    }
  }
  return out;
}

TEST(MosquittoClient, WarningsRaisedWhileBrokerIsDownArriveWhenItReturns) {
  Broker broker("1001");
  ASSERT_TRUE(broker.configured());
  ASSERT_TRUE(broker.start()) << broker.log();
  Probe hmi("hmi-probe", "hmi", "hmi", broker.port(), /*persistent_session=*/true);
  hmi.subscribe_on_connect("its/1001/app/lcrw");
  ASSERT_EQ(hmi.connect(), kReasonSuccess);

  clock::SystemClock clk;
  tb::mqtt::MosquittoClient client(clk, station_config(broker));
  StationPublisher pub(clk, client, PublisherConfig{"its", 1001});
  client.start();
  ASSERT_TRUE(wait_until([&] { return client.connected(); }, 5s));
  pub.publish_warning(warning(2000, 2.0));
  ASSERT_TRUE(hmi.wait_messages(1, 5s));

  broker.stop();
  ASSERT_TRUE(wait_until([&] { return !client.connected(); }, 5s));
  for (int i = 0; i < 5; ++i) {
    pub.publish_warning(warning(2001 + i, 2.5));
  }
  EXPECT_EQ(client.pending(), 5u);

  ASSERT_TRUE(broker.start()) << broker.log();
  ASSERT_TRUE(hmi.wait_messages(6, 15s)) << broker.log();
  const auto got = lcrw_payloads(hmi);
  ASSERT_EQ(got.size(), 6u);
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(got[1 + i]["message"]["other_station_id"], 2001 + i) << "in order";
  }
  EXPECT_TRUE(wait_until([&] { return client.pending() == 0; }, 5s));
  EXPECT_EQ(client.dropped(), 0u);
  EXPECT_GE(client.connections(), 2u);
}

TEST(MosquittoClient, BoundedQueueDropsOldestAndReportsTheCount) {
  Broker broker("1001");
  ASSERT_TRUE(broker.configured());
  // The subscriber's session is made while the broker is up, then the broker goes away before
  // the station ever connects.
  ASSERT_TRUE(broker.start()) << broker.log();
  {
    Probe hmi("hmi-probe", "hmi", "hmi", broker.port(), true);
    hmi.subscribe_on_connect("its/1001/#");
    ASSERT_EQ(hmi.connect(), kReasonSuccess);
  }
  broker.stop();

  clock::SystemClock clk;
  tb::mqtt::MosquittoClient client(clk, station_config(broker, 3));
  StationPublisher pub(clk, client, PublisherConfig{"its", 1001});
  client.start();
  for (int i = 0; i < 5; ++i) {
    pub.publish_warning(warning(3000 + i, 1.0));
  }
  EXPECT_EQ(client.dropped(), 2u);
  EXPECT_EQ(client.pending(), 3u);

  ASSERT_TRUE(broker.start()) << broker.log();
  Probe hmi("hmi-probe", "hmi", "hmi", broker.port(), true);
  hmi.subscribe_on_connect("its/1001/#");
  ASSERT_EQ(hmi.connect(), kReasonSuccess);
  ASSERT_TRUE(wait_until([&] { return lcrw_payloads(hmi).size() >= 3; }, 15s)) << broker.log();
  const auto got = lcrw_payloads(hmi);
  ASSERT_EQ(got.size(), 3u);
  EXPECT_EQ(got[0]["message"]["other_station_id"], 3002);
  EXPECT_EQ(got[2]["message"]["other_station_id"], 3004);
  // The retained status tells subscribers how many were lost.
  bool status_seen = false;
  for (const auto& [topic, payload] : hmi.messages()) {
    if (topic == "its/1001/status") {
      const json s = json::parse(payload);
      if (s["online"] == true) {
        EXPECT_EQ(s["dropped"], 2);
        status_seen = true;
      }
    }
  }
  EXPECT_TRUE(status_seen);
}

TEST(MosquittoClient, StopPublishesOfflineStatus) {
  Broker broker("1001");
  ASSERT_TRUE(broker.configured());
  ASSERT_TRUE(broker.start()) << broker.log();
  clock::SystemClock clk;
  {
    tb::mqtt::MosquittoClient client(clk, station_config(broker));
    client.start();
    ASSERT_TRUE(wait_until([&] { return client.connected(); }, 5s));
    client.stop();
  }
  Probe hmi("hmi-probe", "hmi", "hmi", broker.port());
  hmi.subscribe_on_connect("its/1001/status");
  ASSERT_EQ(hmi.connect(), kReasonSuccess);
  ASSERT_TRUE(hmi.wait_messages(1, 3s));
  EXPECT_EQ(json::parse(hmi.messages().back().second)["online"], false);
}

}  // namespace
}  // namespace tb::its::apps::mqtt
