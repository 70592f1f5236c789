// Integration: QoS 0 messages held for one flush() (its-station's batch per wake-up, issue 33)
// reach a real Mosquitto all and in order, and a QoS 1 message does not overtake what is held.
// The QoS 0 packets are this client's own encoding, sent a batch at a time: a broker that stops
// reading (SIGSTOP) must never see a packet cut or two interleaved, only whole ones in order.
#include <gtest/gtest.h>

#include <functional>
#include <mutex>
#include <optional>
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
  std::size_t size() {
    std::lock_guard l(mu);
    return got.size();
  }
  void clear() {
    std::lock_guard l(mu);
    got.clear();
  }
};

ClientConfig account(const Broker& b, const std::string& user, const std::string& password) {
  ClientConfig c;
  c.port = b.port();
  c.client_id = user + "-batch-test";
  c.username = user;
  c.password = password;
  c.reconnect_min_s = 1;
  c.reconnect_max_s = 1;
  return c;
}

class MosquittoClientBatch : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(broker_.configured());
    ASSERT_TRUE(broker_.start()) << broker_.log();
    ClientConfig r = account(broker_, "hmi", "hmi");
    r.subscriptions = {"its/1001/app/lcrw", "its/+/in/cam/+"};
    view_.emplace(clk_, r);
    view_->set_message_handler(
        [this](std::string_view t, std::string_view p) { inbox_.add(t, p); });
    view_->start();
    station_.emplace(clk_, account(broker_, "station-1001", broker_.password(1001)));
    // The owner's loop, by hand: what a flush request posts waits here until run_loop().
    station_->set_flush_request([this] { posted_.push_back([this] { station_->flush(); }); });
    station_->start();
    ASSERT_TRUE(wait_until([&] { return view_->connected() && station_->connected(); }, 5s));
    // The reader's subscriptions are in place once a probe reaches it (QoS 1: not held).
    ASSERT_TRUE(wait_until(
        [&] {
          station_->publish("its/1001/app/lcrw", "probe", Qos::kAtLeastOnce, false);
          return wait_until([&] { return inbox_.size() > 0; }, 200ms);
        },
        5s));
    ASSERT_TRUE(wait_until([&] { return station_->pending() == 0; }, 5s));
    std::this_thread::sleep_for(100ms);  // a late probe's copy
    inbox_.clear();
    posted_.clear();
  }

  void run_loop() {
    auto p = std::move(posted_);
    posted_.clear();
    for (auto& f : p)
      f();
  }

  Broker broker_{"1001"};
  clock::SystemClock clk_;
  Inbox inbox_;
  std::optional<MosquittoClient> view_;
  std::optional<MosquittoClient> station_;
  std::vector<std::function<void()>> posted_;
};

TEST_F(MosquittoClientBatch, HeldUntilFlushThenAllArriveInOrder) {
  constexpr int kMessages = 60;
  for (int i = 0; i < kMessages; ++i)
    station_->publish("its/1001/in/cam/1002", std::to_string(i), Qos::kAtMostOnce, false);
  // One request for the whole batch, and nothing written before the loop runs it.
  ASSERT_EQ(posted_.size(), 1u);
  EXPECT_EQ(station_->batches(), 0u);
  std::this_thread::sleep_for(200ms);
  EXPECT_EQ(inbox_.size(), 0u);

  run_loop();
  EXPECT_EQ(station_->batches(), 1u);
  EXPECT_EQ(station_->batched_messages(), static_cast<std::uint64_t>(kMessages));
  ASSERT_TRUE(wait_until([&] { return inbox_.size() >= kMessages; }, 5s)) << inbox_.size();
  const auto got = inbox_.copy();
  ASSERT_EQ(got.size(), static_cast<std::size_t>(kMessages));
  for (int i = 0; i < kMessages; ++i) {
    EXPECT_EQ(got[i].first, "its/1001/in/cam/1002");
    EXPECT_EQ(got[i].second, std::to_string(i)) << "message " << i;
  }

  // The next publish starts a new batch with a new request.
  station_->publish("its/1001/in/cam/1003", "next", Qos::kAtMostOnce, false);
  ASSERT_EQ(posted_.size(), 1u);
  run_loop();
  ASSERT_TRUE(wait_until([&] { return inbox_.size() == kMessages + 1; }, 5s));
  EXPECT_EQ(inbox_.copy().back().second, "next");
  EXPECT_EQ(station_->batches(), 2u);
}

TEST_F(MosquittoClientBatch, QosOneWritesWhatIsHeldFirst) {
  for (int i = 0; i < 5; ++i)
    station_->publish("its/1001/in/cam/1002", std::to_string(i), Qos::kAtMostOnce, false);
  station_->publish("its/1001/app/lcrw", R"({"event":"raised"})", Qos::kAtLeastOnce, false);
  // The warning went out at once, behind the held CAMs, without waiting for the loop.
  ASSERT_TRUE(wait_until([&] { return inbox_.size() >= 6; }, 5s)) << inbox_.size();
  const auto got = inbox_.copy();
  ASSERT_EQ(got.size(), 6u);
  for (int i = 0; i < 5; ++i)
    EXPECT_EQ(got[i].second, std::to_string(i));
  EXPECT_EQ(got[5].first, "its/1001/app/lcrw");
  // The loop's flush finds nothing left to write.
  run_loop();
  EXPECT_EQ(station_->batches(), 1u);
  EXPECT_EQ(station_->batched_messages(), 5u);
}

TEST_F(MosquittoClientBatch, StopWritesWhatIsHeld) {
  station_->publish("its/1001/in/cam/1002", "last", Qos::kAtMostOnce, false);
  station_->stop();
  ASSERT_TRUE(wait_until([&] { return inbox_.size() >= 1; }, 5s));
  EXPECT_EQ(inbox_.copy().front().second, "last");
}

// A payload that says which message it is and whose every byte is checkable.
std::string numbered(int i, std::size_t size) {
  std::string p = std::to_string(i) + ":";
  while (p.size() < size) {
    p.push_back(static_cast<char>('a' + (i + p.size()) % 26));
  }
  return p;
}

TEST_F(MosquittoClientBatch, BrokerThatStopsReadingSeesOnlyWholePacketsInOrder) {
  // Far more than the loopback socket buffers hold (a few MiB each way), in batches.
  constexpr std::size_t kSize = 16 * 1024;
  constexpr int kPerFlush = 64;
  constexpr int kFlushes = 24;
  broker_.pause();
  int sent = 0;
  for (int f = 0; f < kFlushes; ++f) {
    for (int k = 0; k < kPerFlush; ++k, ++sent)
      station_->publish("its/1001/in/cam/1002", numbered(sent, kSize), Qos::kAtMostOnce, false);
    run_loop();
  }
  EXPECT_GE(station_->raw_deferred(), 1u) << "the socket never filled: the test proves nothing";
  EXPECT_GT(station_->raw_discarded(), 0u);
  // A warning while our bytes wait: it must go after them, not inside them.
  station_->publish("its/1001/app/lcrw", R"({"event":"raised"})", Qos::kAtLeastOnce, false);
  std::this_thread::sleep_for(300ms);
  broker_.resume();
  // More warnings while the backlog drains: the socket has room again now and then, and
  // libmosquitto must still not write before our half-written packet is done.
  constexpr int kLateWarnings = 100;
  for (int w = 0; w < kLateWarnings; ++w) {
    station_->publish("its/1001/app/lcrw", "late " + std::to_string(w), Qos::kAtLeastOnce, false);
    std::this_thread::sleep_for(1ms);
  }

  const std::string last_warning = "late " + std::to_string(kLateWarnings - 1);
  ASSERT_TRUE(wait_until(
      [&] {
        const auto got = inbox_.copy();
        return !got.empty() && got.back().second == last_warning;
      },
      20s))
      << inbox_.size() << " messages; broker log:\n"
      << broker_.log();
  const auto got = inbox_.copy();
  int last = -1;
  std::vector<std::string> warnings;
  for (std::size_t j = 0; j < got.size(); ++j) {
    if (got[j].first == "its/1001/app/lcrw") {
      warnings.push_back(got[j].second);
      continue;
    }
    ASSERT_EQ(got[j].first, "its/1001/in/cam/1002") << j;
    EXPECT_TRUE(warnings.empty()) << "a CAM published before every warning came after one";
    const int i = std::stoi(got[j].second);
    EXPECT_GT(i, last) << "out of order at " << j;
    // Not EXPECT_EQ: a 16 KiB payload printed whole buries the report.
    EXPECT_TRUE(got[j].second == numbered(i, kSize))
        << "message " << i << " arrived damaged (" << got[j].second.size() << " bytes)";
    last = i;
  }
  ASSERT_EQ(warnings.size(), 1u + kLateWarnings);
  EXPECT_EQ(warnings.front(), R"({"event":"raised"})");
  for (int w = 0; w < kLateWarnings; ++w)
    EXPECT_EQ(warnings[1 + w], "late " + std::to_string(w));
  // What waited in the sockets and our backlog arrived; what came beyond it was discarded whole.
  EXPECT_GT(got.size(), 100u);
  EXPECT_LT(got.size(), static_cast<std::size_t>(sent) + 1);
  EXPECT_EQ(station_->connections(), 1u) << "the broker dropped the connection:\n" << broker_.log();
  EXPECT_EQ(broker_.log().find("protocol error"), std::string::npos) << broker_.log();

  // And the connection goes on as before.
  inbox_.clear();
  station_->publish("its/1001/in/cam/1003", "after", Qos::kAtMostOnce, false);
  run_loop();
  ASSERT_TRUE(wait_until([&] { return inbox_.size() >= 1; }, 5s));
  EXPECT_EQ(inbox_.copy().front().second, "after");
}

TEST(MosquittoClientStall, ABrokerSilentForAKeepaliveLosesTheConnectionAndItComesBack) {
  Broker broker{"1001"};
  ASSERT_TRUE(broker.configured());
  ASSERT_TRUE(broker.start()) << broker.log();
  clock::SystemClock clk;
  ClientConfig c = account(broker, "station-1001", broker.password(1001));
  c.keepalive_s = 5;  // libmosquitto's least
  MosquittoClient station(clk, c);
  std::vector<std::function<void()>> posted;
  station.set_flush_request([&] { posted.push_back([&] { station.flush(); }); });
  station.start();
  ASSERT_TRUE(wait_until([&] { return station.connected(); }, 5s));

  broker.pause();
  // Fill the sockets until our bytes wait.
  for (int f = 0; f < 40 && station.raw_deferred() == 0; ++f) {
    for (int k = 0; k < 64; ++k)
      station.publish("its/1001/in/cam/1002", numbered(k, 16 * 1024), Qos::kAtMostOnce, false);
    auto p = std::move(posted);
    posted.clear();
    for (auto& fn : p)
      fn();
  }
  ASSERT_GE(station.raw_deferred(), 1u);
  // Our writer gives the connection up after a keepalive without progress.
  ASSERT_TRUE(wait_until([&] { return !station.connected(); }, 12s));
  broker.resume();
  ASSERT_TRUE(wait_until([&] { return station.connected() && station.connections() == 2; }, 10s))
      << broker.log();
  station.stop();
}

}  // namespace
}  // namespace tb::mqtt
