#include "sim-client/v2x/subscriber.hpp"

#include <unistd.h>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

namespace tb::client::v2x {

V2xSubscriber::V2xSubscriber(const clock::Clock& clock, V2xMonitor& monitor,
                             SubscriberOptions options)
    : clock_(clock), monitor_(monitor), options_(std::move(options)) {
  mqtt::ClientConfig cfg;
  cfg.host = options_.host;
  cfg.port = options_.port;
  // Unique per process, so that two views on one machine do not take over each other's session.
  cfg.client_id = fmt::format("sim-client-view-{}", ::getpid());
  cfg.username = options_.username;
  cfg.password = options_.password;
  cfg.subscriptions = monitor_.subscriptions();
  cfg.subscribe_qos = mqtt::Qos::kAtLeastOnce;
  cfg.reconnect_min_s = 1;
  cfg.reconnect_max_s = 8;
  client_ = std::make_unique<mqtt::MosquittoClient>(clock_, std::move(cfg));
  client_->set_message_handler([this](std::string_view topic, std::string_view payload) {
    const auto before = monitor_.rejected();
    if (!monitor_.on_message(topic, payload, clock_.steady_now())) {
      const auto n = monitor_.rejected();
      // Log the first bad message, then every 1000th: a broken publisher must not flood the log.
      if (n != before && (n == 1 || n % 1000 == 0))
        spdlog::warn("mqtt: ignored message ({} so far): {}", n, monitor_.last_error());
    }
  });
}

V2xSubscriber::~V2xSubscriber() {
  stop();
}

void V2xSubscriber::start() {
  client_->start();
}
void V2xSubscriber::stop() {
  client_->stop(std::chrono::milliseconds{0});
}
bool V2xSubscriber::connected() const {
  return client_->connected();
}

std::string V2xSubscriber::status() const {
  const std::string where = fmt::format("MQTT {}:{}", options_.host, options_.port);
  if (client_->connected())
    return where;
  const int rc = client_->last_connack();
  if (rc > 0)
    return fmt::format("{}: refused (CONNACK {}), user '{}'", where, rc, options_.username);
  return where + ": connecting";
}

}  // namespace tb::client::v2x
