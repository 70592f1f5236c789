// Integration: QoS 0 messages held for one flush() (its-station's batch per wake-up, issue 33)
// reach a real Mosquitto all and in order, and a QoS 1 message does not overtake what is held.
#include <gtest/gtest.h>

#include <functional>
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

}  // namespace
}  // namespace tb::mqtt
