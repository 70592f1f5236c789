// Integration: MosquittoClient as a reader (the read-only `hmi` account of the project's broker
// configuration) on a real Mosquitto: it receives what a station publishes on the topics it
// subscribed to, nothing else, and subscribes again after the broker comes back.
#include <gtest/gtest.h>

#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "common/clock/clock.hpp"
#include "common/mqtt/mosquitto_client.hpp"
#include "common/mqtt/tests/test_broker.hpp"

namespace tb::mqtt {
namespace {

using namespace std::chrono_literals;
using testing::Broker;
using testing::wait_until;

struct Inbox {
  std::mutex mu;
  std::vector<std::pair<std::string, std::string>> got;
  void add(std::string_view t, std::string_view p) {
    std::lock_guard l(mu);
    got.emplace_back(t, p);
  }
  std::vector<std::pair<std::string, std::string>> copy() {
    std::lock_guard l(mu);
    return got;
  }
  bool has(const std::string& topic, const std::string& payload) {
    std::lock_guard l(mu);
    for (const auto& [t, p] : got)
      if (t == topic && p == payload)
        return true;
    return false;
  }
};

ClientConfig account(const Broker& b, const std::string& user, const std::string& password) {
  ClientConfig c;
  c.port = b.port();
  c.client_id = user + "-test";
  c.username = user;
  c.password = password;
  c.reconnect_min_s = 1;
  c.reconnect_max_s = 1;
  return c;
}

ClientConfig station(const Broker& b) {
  return account(b, "station-1001", b.password(1001));
}

ClientConfig reader(const Broker& b) {
  ClientConfig c = account(b, "hmi", "hmi");
  c.subscriptions = {"its/1001/app/lcrw", "its/+/in/cam/+"};
  return c;
}

TEST(MosquittoClientSubscribe, ReaderGetsSubscribedTopicsAndResubscribesAfterBrokerRestart) {
  Broker broker("1001");
  ASSERT_TRUE(broker.configured());
  ASSERT_TRUE(broker.start()) << broker.log();
  clock::SystemClock clk;
  Inbox inbox;
  MosquittoClient view(clk, reader(broker));
  view.set_message_handler([&](std::string_view t, std::string_view p) { inbox.add(t, p); });
  view.start();
  MosquittoClient st(clk, station(broker));
  st.start();
  ASSERT_TRUE(wait_until([&] { return view.connected() && st.connected(); }, 5s));

  // QoS 1 warnings are kept until the broker acknowledges them; publish until the reader's
  // subscription (sent on its CONNACK) is in place and one arrives.
  ASSERT_TRUE(wait_until(
      [&] {
        st.publish("its/1001/app/lcrw", R"({"event":"raised"})", Qos::kAtLeastOnce, false);
        return inbox.has("its/1001/app/lcrw", R"({"event":"raised"})");
      },
      5s));
  st.publish("its/1001/in/cam/1002", "cam", Qos::kAtLeastOnce, false);
  st.publish("its/1001/state", "not subscribed", Qos::kAtLeastOnce, false);
  ASSERT_TRUE(wait_until([&] { return inbox.has("its/1001/in/cam/1002", "cam"); }, 5s));
  // The state topic was published before the CAM on the same connection: had it been
  // delivered, it would be here by now.
  for (const auto& [t, p] : inbox.copy())
    EXPECT_NE(t, "its/1001/state");

  broker.stop();
  ASSERT_TRUE(wait_until([&] { return !view.connected(); }, 5s));
  ASSERT_TRUE(broker.start()) << broker.log();
  ASSERT_TRUE(wait_until([&] { return view.connected() && st.connected(); }, 15s)) << broker.log();
  EXPECT_GE(view.connections(), 2u);
  ASSERT_TRUE(wait_until(
      [&] {
        st.publish("its/1001/app/lcrw", R"({"event":"cleared"})", Qos::kAtLeastOnce, false);
        return inbox.has("its/1001/app/lcrw", R"({"event":"cleared"})");
      },
      5s))
      << broker.log();
  view.stop();
  st.stop();
}

}  // namespace
}  // namespace tb::mqtt
