// its-mqtt-latency: how long an LCRW warning takes from StationPublisher::publish_warning() to
// a subscriber, through a real Mosquitto configured by docker/mosquitto/gen-broker-config.
//
//   its-mqtt-latency --config DIR [--station ID] [--count N] [--rate HZ]
//
// DIR is gen-broker-config's --out (credentials.json and mosquitto.conf); the broker must be
// running. Prints median, p99 and max in microseconds; exits 1 if messages went missing.
#include <mosquitto.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <fstream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <regex>
#include <thread>
#include <vector>

#include "common/mqtt/mosquitto_client.hpp"
#include "its-station/apps/mqtt/publisher.hpp"

namespace {

using Clock = std::chrono::steady_clock;
using tb::mqtt::MqttError;

struct Receiver {
  std::mutex mu;
  std::map<std::uint32_t, Clock::time_point> arrived;
  std::atomic<bool> subscribed{false};
};

int tcp_port_of(const std::string& conf_path) {
  std::ifstream f(conf_path);
  const std::regex listener(R"(^listener\s+(\d+))");
  std::string line;
  std::smatch m;
  while (std::getline(f, line)) {
    if (std::regex_search(line, m, listener)) {
      return std::stoi(m[1]);  // the first listener is the TCP one (mosquitto.conf.in)
    }
  }
  throw MqttError("no listener in " + conf_path);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"MQTT latency of LCRW warnings through the testbed's broker"};
  std::string dir;
  std::uint32_t station = 0;
  int count = 1000;
  double rate = 100.0;
  app.add_option("--config", dir, "gen-broker-config output folder")->required();
  app.add_option("--station", station, "station id to publish as (default: the first)");
  app.add_option("--count", count, "warnings to send")->check(CLI::Range(1, 1000000));
  app.add_option("--rate", rate, "warnings per second")->check(CLI::Range(0.1, 100000.0));
  CLI11_PARSE(app, argc, argv);
  spdlog::set_level(spdlog::level::warn);

  try {
    std::ifstream cf(dir + "/credentials.json");
    if (!cf) {
      throw MqttError(dir + "/credentials.json: cannot read");
    }
    const auto creds = nlohmann::json::parse(cf);
    if (station == 0) {
      station = static_cast<std::uint32_t>(std::stoul(creds["stations"].begin().key()));
    }
    const auto& sc = creds["stations"].at(std::to_string(station));
    const auto& reader = creds["readers"].begin().value();
    const int port = tcp_port_of(dir + "/mosquitto.conf");
    const std::string topic = "its/" + std::to_string(station) + "/app/lcrw";

    Receiver rx;
    mosquitto_lib_init();
    mosquitto* sub = mosquitto_new("latency-reader", true, &rx);
    mosquitto_int_option(sub, MOSQ_OPT_TCP_NODELAY, 1);
    mosquitto_username_pw_set(sub, reader["username"].get<std::string>().c_str(),
                              reader["password"].get<std::string>().c_str());
    mosquitto_subscribe_callback_set(sub, [](mosquitto*, void* p, int, int, const int*) {
      static_cast<Receiver*>(p)->subscribed = true;
    });
    mosquitto_message_callback_set(sub, [](mosquitto*, void* p, const mosquitto_message* m) {
      const auto now = Clock::now();
      const auto j = nlohmann::json::parse(std::string(static_cast<const char*>(m->payload),
                                                       static_cast<std::size_t>(m->payloadlen)),
                                           nullptr, false);
      if (j.is_discarded()) {
        return;
      }
      auto* r = static_cast<Receiver*>(p);
      std::lock_guard l(r->mu);
      r->arrived.emplace(j["message"]["other_station_id"].get<std::uint32_t>(), now);
    });
    if (mosquitto_connect(sub, "127.0.0.1", port, 10) != MOSQ_ERR_SUCCESS) {
      throw MqttError("reader cannot connect to 127.0.0.1:" + std::to_string(port));
    }
    mosquitto_subscribe(sub, nullptr, topic.c_str(), 1);
    mosquitto_loop_start(sub);

    tb::clock::SystemClock clk;
    tb::mqtt::ClientConfig cc;
    cc.port = port;
    cc.client_id = "station-" + std::to_string(station) + "-latency";
    cc.username = sc["username"];
    cc.password = sc["password"];
    cc.queue_capacity = static_cast<std::size_t>(count);
    cc.publish_prefix = "its/" + std::to_string(station) + "/";
    tb::mqtt::MosquittoClient client(clk, cc);
    tb::its::apps::mqtt::StationPublisher pub(clk, client, {"its", station});
    client.start();
    const auto ready_by = Clock::now() + std::chrono::seconds(5);
    while ((!client.connected() || !rx.subscribed) && Clock::now() < ready_by) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    if (!client.connected() || !rx.subscribed) {
      throw MqttError("station or reader not connected within 5 s (last CONNACK " +
                      std::to_string(client.last_connack()) + ")");
    }

    std::vector<Clock::time_point> sent(static_cast<std::size_t>(count));
    const auto period = std::chrono::duration<double>(1.0 / rate);
    const auto t0 = Clock::now();
    for (int i = 0; i < count; ++i) {
      std::this_thread::sleep_until(t0 + std::chrono::duration_cast<Clock::duration>(period * i));
      tb::its::apps::LcrwWarning w;
      w.station_id = station;
      w.other_station_id = static_cast<std::uint32_t>(i);
      w.ttc_s = 2.5;
      w.updated_at = clk.wall_now();
      sent[static_cast<std::size_t>(i)] = Clock::now();
      pub.publish_warning(w);
    }
    const auto wait_by = Clock::now() + std::chrono::seconds(10);
    while (Clock::now() < wait_by) {
      {
        std::lock_guard l(rx.mu);
        if (rx.arrived.size() >= static_cast<std::size_t>(count)) {
          break;
        }
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    client.stop();
    mosquitto_disconnect(sub);
    mosquitto_loop_stop(sub, false);
    mosquitto_destroy(sub);

    std::vector<double> us;
    {
      std::lock_guard l(rx.mu);
      for (const auto& [i, t] : rx.arrived) {
        if (i < sent.size()) {
          us.push_back(std::chrono::duration<double, std::micro>(t - sent[i]).count());
        }
      }
    }
    std::sort(us.begin(), us.end());
    if (us.empty()) {
      throw MqttError("no warning arrived");
    }
    auto pct = [&](double p) {
      return us[std::min(us.size() - 1, static_cast<std::size_t>(p * (us.size() - 1) + 0.5))];
    };
    fmt::print("warnings sent {} received {} at {} Hz\n", count, us.size(), rate);
    fmt::print("latency us: median {:.0f} p90 {:.0f} p99 {:.0f} max {:.0f}\n", pct(0.5), pct(0.9),
               pct(0.99), us.back());
    return us.size() == static_cast<std::size_t>(count) ? 0 : 1;
  } catch (const std::exception& e) {
    fmt::print(stderr, "its-mqtt-latency: {}\n", e.what());
    return 1;
  }
}
