#include "common/mqtt/mosquitto_client.hpp"

#include <mosquitto.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <spdlog/spdlog.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <mutex>
#include <nlohmann/json.hpp>

#include "common/mqtt/publish_packet.hpp"

namespace tb::mqtt {
namespace {

void init_library_once() {
  static std::once_flag once;
  std::call_once(once, [] { mosquitto_lib_init(); });
}

}  // namespace

MosquittoClient::MosquittoClient(const clock::Clock& clock, ClientConfig cfg)
    : clock_(clock), cfg_(std::move(cfg)), outbox_(cfg_.queue_capacity) {
  if (!cfg_.publish_prefix.empty() && !cfg_.status_topic.empty() &&
      !cfg_.status_topic.starts_with(cfg_.publish_prefix)) {
    throw MqttError("mqtt: status topic '" + cfg_.status_topic + "' is outside the prefix '" +
                    cfg_.publish_prefix + "'");
  }
  init_library_once();
  mosq_ = mosquitto_new(cfg_.client_id.empty() ? nullptr : cfg_.client_id.c_str(), true, this);
  if (mosq_ == nullptr) {
    throw MqttError("mqtt: cannot create a libmosquitto client (client id '" + cfg_.client_id +
                    "')");
  }
  mosquitto_connect_callback_set(mosq_, &MosquittoClient::on_connect);
  mosquitto_disconnect_callback_set(mosq_, &MosquittoClient::on_disconnect);
  mosquitto_publish_callback_set(mosq_, &MosquittoClient::on_publish);
  mosquitto_message_callback_set(mosq_, &MosquittoClient::on_message);
  // Not mosquitto_threaded_set: publish() writes at once in its own thread (see the header).
  // Every call into libmosquitto that may write is made under mutex_, so that the QoS 0 bytes
  // this class writes itself never land inside one of libmosquitto's packets.
  // Warnings are small and urgent: no Nagle delay behind an unacknowledged segment.
  mosquitto_int_option(mosq_, MOSQ_OPT_TCP_NODELAY, 1);
  mosquitto_reconnect_delay_set(mosq_, cfg_.reconnect_min_s, cfg_.reconnect_max_s, true);
  if (!cfg_.username.empty()) {
    if (const int rc =
            mosquitto_username_pw_set(mosq_, cfg_.username.c_str(), cfg_.password.c_str());
        rc != MOSQ_ERR_SUCCESS) {
      mosquitto_destroy(mosq_);
      throw MqttError(std::string("mqtt: bad credentials for user '") + cfg_.username +
                      "': " + mosquitto_strerror(rc));
    }
  }
  wake_fd_ = ::eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
  if (wake_fd_ < 0) {
    mosquitto_destroy(mosq_);
    throw MqttError(std::string("mqtt: cannot make the network thread's eventfd: ") +
                    std::strerror(errno));
  }
  if (!cfg_.status_topic.empty()) {
    const std::string will = status_payload_locked(false);
    if (const int rc = mosquitto_will_set(mosq_, cfg_.status_topic.c_str(),
                                          static_cast<int>(will.size()), will.data(), 1, true);
        rc != MOSQ_ERR_SUCCESS) {
      mosquitto_destroy(mosq_);
      ::close(wake_fd_);
      throw MqttError("mqtt: bad status topic '" + cfg_.status_topic +
                      "': " + mosquitto_strerror(rc));
    }
  }
}

MosquittoClient::~MosquittoClient() {
  stop();
  mosquitto_destroy(mosq_);
  ::close(wake_fd_);
}

void MosquittoClient::set_message_handler(MessageHandler handler) {
  std::lock_guard lock(mutex_);
  handler_ = std::move(handler);
}

void MosquittoClient::start() {
  std::lock_guard lock(mutex_);
  if (started_) {
    return;
  }
  started_ = true;
  stopping_ = false;
  thread_ = std::thread([this] { run(); });
}

void MosquittoClient::run() {
  unsigned delay_s = std::max(1u, cfg_.reconnect_min_s);
  bool reported = false;
  while (true) {
    const int rc = mosquitto_connect(mosq_, cfg_.host.c_str(), cfg_.port, cfg_.keepalive_s);
    if (rc == MOSQ_ERR_SUCCESS) {
      {
        std::lock_guard lock(mutex_);
        if (stopping_) {
          break;
        }
      }
      delay_s = std::max(1u, cfg_.reconnect_min_s);
      reported = false;
      const int serve_rc = serve();
      apply_events();
      std::lock_guard lock(mutex_);
      connected_ = false;
      drop_raw_locked();
      if (stopping_) {
        break;
      }
      // on_disconnect has said so when the broker went away; this is the cause.
      spdlog::debug("mqtt: connection ended ({}); reconnecting", mosquitto_strerror(serve_rc));
    } else if (!reported) {
      reported = true;
      spdlog::warn("mqtt: broker {}:{} not reachable ({}); retrying with backoff up to {} s",
                   cfg_.host, cfg_.port,
                   rc == MOSQ_ERR_ERRNO ? std::strerror(errno) : mosquitto_strerror(rc),
                   cfg_.reconnect_max_s);
    }
    std::unique_lock lock(mutex_);
    if (wake_.wait_for(lock, std::chrono::seconds{delay_s}, [&] { return stopping_; })) {
      break;
    }
    delay_s = std::min(delay_s * 2, std::max(delay_s, cfg_.reconnect_max_s));
  }
}

int MosquittoClient::serve() {
  // The poll's timeout bounds how late keepalive pings and stop() are seen; a keepalive of
  // a second or more needs nothing finer.
  constexpr int kPollMs = 500;
  while (true) {
    int sock = -1;
    bool ours = false;  // a packet of ours is half written: the socket is ours until it is not
    bool want_write = false;
    {
      std::lock_guard lock(mutex_);
      if (stopping_) {
        return MOSQ_ERR_SUCCESS;
      }
      sock = mosquitto_socket(mosq_);
      ours = raw_pending_locked() > 0;
      want_write = ours || mosquitto_want_write(mosq_);
    }
    if (sock < 0) {
      return MOSQ_ERR_NO_CONN;
    }
    // While our bytes wait for room, libmosquitto may write nothing (an acknowledgement, a
    // ping), so it does not read either: polling for input then would only spin.
    pollfd fds[2] = {
        {sock, static_cast<short>((ours ? 0 : POLLIN) | (want_write ? POLLOUT : 0)), 0},
        {wake_fd_, POLLIN, 0}};
    const int n = ::poll(fds, 2, kPollMs);
    if (n < 0 && errno != EINTR) {
      return MOSQ_ERR_ERRNO;
    }
    if (n > 0 && (fds[1].revents & POLLIN) != 0) {
      std::uint64_t count = 0;
      [[maybe_unused]] const ssize_t r = ::read(wake_fd_, &count, sizeof count);
    }
    const short rev = n > 0 ? fds[0].revents : 0;
    int rc = MOSQ_ERR_SUCCESS;
    {
      std::lock_guard lock(mutex_);
      if (raw_pending_locked() > 0 && (rev & (POLLOUT | POLLERR | POLLHUP)) != 0) {
        send_raw_locked();
      }
      if (raw_pending_locked() > 0) {
        // The broker has taken nothing for a keepalive period: as libmosquitto would when
        // its ping goes unanswered, give the connection up (reconnecting starts clean).
        if (clock_.steady_now() - raw_stalled_since_ > std::chrono::seconds{cfg_.keepalive_s}) {
          spdlog::warn("mqtt: the broker {}:{} took no data for {} s; reconnecting", cfg_.host,
                       cfg_.port, cfg_.keepalive_s);
          ::shutdown(sock, SHUT_RDWR);
          drop_raw_locked();
        }
        continue;
      }
      if ((rev & (POLLIN | POLLHUP | POLLERR)) != 0) {
        rc = mosquitto_loop_read(mosq_, 1);
      }
      if (rc == MOSQ_ERR_SUCCESS && (rev & POLLOUT) != 0 && mosquitto_want_write(mosq_)) {
        rc = mosquitto_loop_write(mosq_, 1);
      }
      if (rc == MOSQ_ERR_SUCCESS) {
        rc = mosquitto_loop_misc(mosq_);  // keepalive
      }
      flush_locked();  // QoS 1 messages that waited behind our bytes
    }
    apply_events();
    if (rc != MOSQ_ERR_SUCCESS) {
      return rc;
    }
  }
}

void MosquittoClient::wake_network() {
  const std::uint64_t one = 1;
  [[maybe_unused]] const ssize_t w = ::write(wake_fd_, &one, sizeof one);
}

void MosquittoClient::stop(std::chrono::milliseconds grace) {
  std::unique_lock lock(mutex_);
  if (!started_) {
    return;
  }
  started_ = false;
  write_held_locked();  // the owner's loop may have ended before its flush() ran
  if (connected_ && raw_pending_locked() == 0 && !cfg_.status_topic.empty()) {
    const std::string s = status_payload_locked(false);
    int mid = 0;
    if (mosquitto_publish(mosq_, &mid, cfg_.status_topic.c_str(), static_cast<int>(s.size()),
                          s.data(), 1, true) == MOSQ_ERR_SUCCESS) {
      status_mid_ = mid;
      acked_.wait_for(lock, grace, [&] { return status_mid_ == -1 || !connected_; });
    }
  }
  stopping_ = true;
  wake_.notify_all();
  if (raw_pending_locked() == 0) {
    mosquitto_disconnect(mosq_);
  } else if (const int sock = mosquitto_socket(mosq_); sock >= 0) {
    // A DISCONNECT now would land inside our half-written packet; the broker publishes the
    // will ("offline") for a connection that just ends, which is what stopping means here.
    ::shutdown(sock, SHUT_RDWR);
  }
  drop_raw_locked();
  lock.unlock();
  wake_network();
  if (thread_.joinable()) {
    thread_.join();
  }
  lock.lock();
  connected_ = false;
  held_.clear();
  drop_raw_locked();
}

void MosquittoClient::publish(std::string_view topic, std::string payload, Qos qos, bool retain) {
  std::lock_guard lock(mutex_);
  if (!cfg_.publish_prefix.empty() && !topic.starts_with(cfg_.publish_prefix)) {
    ++refused_;
    spdlog::error("mqtt: refusing to publish to '{}': a station publishes only under '{}'", topic,
                  cfg_.publish_prefix);
    return;
  }
  if (qos == Qos::kAtMostOnce) {
    if (request_flush_) {
      // Held even while disconnected: flush() decides, as late as possible.
      const bool first = held_.empty();
      held_.push_back(OutMessage{std::string(topic), std::move(payload), qos, retain});
      if (first) {
        request_flush_();  // under mutex_: it only posts (see the header)
      }
      return;
    }
    if (connected_) {
      held_.push_back(OutMessage{std::string(topic), std::move(payload), qos, retain});
      write_held_locked();
    }
    return;
  }
  write_held_locked();
  if (outbox_.push(OutMessage{std::string(topic), std::move(payload), qos, retain})) {
    spdlog::warn("mqtt: queue full ({} messages), dropped the oldest; {} dropped so far",
                 outbox_.capacity(), outbox_.dropped());
  }
  flush_locked();
  wake_if_unwritten_locked();
}

void MosquittoClient::set_flush_request(std::function<void()> request_flush) {
  std::lock_guard lock(mutex_);
  request_flush_ = std::move(request_flush);
}

void MosquittoClient::flush() {
  std::lock_guard lock(mutex_);
  write_held_locked();
}

void MosquittoClient::write_held_locked() {
  if (held_.empty()) {
    return;
  }
  if (!connected_) {
    held_.clear();
    return;
  }
  if (raw_pending_locked() == 0 && mosquitto_want_write(mosq_)) {
    // libmosquitto has bytes of its own waiting (a QoS 1 packet the socket did not take whole):
    // ours go behind them, through it.
    for (const OutMessage& m : held_) {
      mosquitto_publish(mosq_, nullptr, m.topic.c_str(), static_cast<int>(m.payload.size()),
                        m.payload.data(), 0, m.retain);
    }
    wake_if_unwritten_locked();
  } else {
    const std::size_t before = raw_.size();
    for (const OutMessage& m : held_) {
      if (raw_pending_locked() > kRawBacklogMax) {
        // The broker has not read for a while: a QoS 0 message may be lost, never cut.
        if (raw_discarded_++ == 0 || raw_discarded_ % 1000 == 0) {
          spdlog::warn("mqtt: the broker {}:{} is not reading; {} QoS 0 messages discarded",
                       cfg_.host, cfg_.port, raw_discarded_);
        }
        continue;
      }
      try {
        append_qos0_publish(raw_, m.topic, m.payload, m.retain);
      } catch (const PacketError& e) {
        ++refused_;
        spdlog::error("{}; message discarded", e.what());
      }
    }
    if (raw_.size() > before) {
      send_raw_locked();
    }
  }
  ++batches_;
  batched_messages_ += held_.size();
  held_.clear();
}

std::size_t MosquittoClient::raw_pending_locked() const {
  return raw_.size() - raw_sent_;
}

void MosquittoClient::send_raw_locked() {
  const int sock = mosquitto_socket(mosq_);
  if (sock < 0) {
    drop_raw_locked();
    return;
  }
  while (raw_pending_locked() > 0) {
    const ssize_t n =
        ::send(sock, raw_.data() + raw_sent_, raw_pending_locked(), MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n > 0) {
      raw_sent_ += static_cast<std::size_t>(n);
      if (raw_waiting_) {
        raw_stalled_since_ = clock_.steady_now();  // it moves: not stalled
      }
      continue;
    }
    if (n < 0 && errno == EINTR) {
      continue;
    }
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      // The network thread finishes it when the socket has room, before libmosquitto writes.
      if (!raw_waiting_) {
        raw_waiting_ = true;
        raw_stalled_since_ = clock_.steady_now();
        ++raw_deferred_;
        wake_network();
      }
      return;
    }
    // The connection is broken; libmosquitto's next read says so and the client reconnects.
    spdlog::debug("mqtt: writing to the broker failed: {}", std::strerror(errno));
    drop_raw_locked();
    return;
  }
  drop_raw_locked();  // all sent
}

void MosquittoClient::drop_raw_locked() {
  raw_.clear();  // keeps its capacity: the next batch allocates nothing
  raw_sent_ = 0;
  raw_waiting_ = false;
}

void MosquittoClient::wake_if_unwritten_locked() {
  // What the socket did not take at once (or what a callback queued) is the network thread's
  // to write when the socket can take it.
  if (mosquitto_want_write(mosq_)) {
    wake_network();
  }
}

void MosquittoClient::flush_locked() {
  while (connected_ && raw_pending_locked() == 0 && inflight_.size() < cfg_.max_inflight &&
         !outbox_.empty()) {
    OutMessage m = *outbox_.pop();
    int mid = 0;
    const int rc =
        mosquitto_publish(mosq_, &mid, m.topic.c_str(), static_cast<int>(m.payload.size()),
                          m.payload.data(), static_cast<int>(m.qos), m.retain);
    if (rc == MOSQ_ERR_SUCCESS ||
        ((rc == MOSQ_ERR_CONN_LOST || rc == MOSQ_ERR_ERRNO) && mid != 0)) {
      // A write that failed on a connection going down leaves the message with libmosquitto,
      // which sends it again after the reconnection.
      inflight_.insert(mid);
    } else if (rc == MOSQ_ERR_NO_CONN) {
      outbox_.push_front(std::move(m));
      connected_ = false;
    } else {
      // Not retryable (bad topic, payload too large): retrying would block the queue.
      spdlog::error("mqtt: cannot publish to '{}': {}; message discarded", m.topic,
                    mosquitto_strerror(rc));
    }
  }
}

std::string MosquittoClient::status_payload_locked(bool online) const {
  return nlohmann::json{{"online", online},
                        {"dropped", outbox_.dropped()},
                        {"pending", outbox_.size() + inflight_.size()},
                        {"timestamp", std::chrono::duration_cast<std::chrono::milliseconds>(
                                          clock_.wall_now().time_since_epoch())
                                          .count()}}
      .dump();
}

// The callbacks run inside libmosquitto while it holds its own locks (on_publish of a QoS 0
// message even in the thread that called publish()). Taking mutex_ there would invert the
// lock order against a thread that holds mutex_ and calls into libmosquitto, so they only
// queue what happened; serve() applies it outside libmosquitto.
void MosquittoClient::on_connect(struct mosquitto*, void* self_ptr, int rc) {
  static_cast<MosquittoClient*>(self_ptr)->queue_event(Event{Event::kConnack, rc, {}, {}});
}

void MosquittoClient::on_message(struct mosquitto*, void* self_ptr,
                                 const struct mosquitto_message* m) {
  if (m == nullptr || m->topic == nullptr) {
    return;
  }
  static_cast<MosquittoClient*>(self_ptr)->queue_event(
      Event{Event::kMessage, 0, m->topic,
            std::string(static_cast<const char*>(m->payload),
                        static_cast<std::size_t>(std::max(0, m->payloadlen)))});
}

void MosquittoClient::on_disconnect(struct mosquitto*, void* self_ptr, int rc) {
  static_cast<MosquittoClient*>(self_ptr)->queue_event(Event{Event::kDisconnect, rc, {}, {}});
}

void MosquittoClient::on_publish(struct mosquitto*, void* self_ptr, int mid) {
  static_cast<MosquittoClient*>(self_ptr)->queue_event(Event{Event::kPublished, mid, {}, {}});
}

void MosquittoClient::queue_event(Event e) {
  std::lock_guard lock(events_mutex_);
  events_.push_back(std::move(e));
}

void MosquittoClient::apply_events() {
  std::vector<Event> events;
  {
    std::lock_guard lock(events_mutex_);
    events.swap(events_);
  }
  if (events.empty()) {
    return;
  }
  std::vector<Event> messages;
  {
    std::lock_guard lock(mutex_);
    for (Event& e : events) {
      switch (e.kind) {
        case Event::kConnack:
          last_connack_ = e.value;
          if (e.value != 0) {
            spdlog::error("mqtt: broker {}:{} refused the connection: {}", cfg_.host, cfg_.port,
                          mosquitto_connack_string(e.value));
            break;
          }
          ++connections_;
          connected_ = true;
          spdlog::info("mqtt: connected to {}:{} as '{}'", cfg_.host, cfg_.port, cfg_.username);
          if (!cfg_.status_topic.empty()) {
            const std::string st = status_payload_locked(true);
            mosquitto_publish(mosq_, nullptr, cfg_.status_topic.c_str(),
                              static_cast<int>(st.size()), st.data(), 1, true);
          }
          for (const auto& topic : cfg_.subscriptions) {
            if (const int src = mosquitto_subscribe(mosq_, nullptr, topic.c_str(),
                                                    static_cast<int>(cfg_.subscribe_qos));
                src != MOSQ_ERR_SUCCESS) {
              spdlog::error("mqtt: cannot subscribe to '{}': {}", topic, mosquitto_strerror(src));
            }
          }
          break;
        case Event::kDisconnect:
          if (connected_ && e.value != 0) {
            spdlog::warn("mqtt: lost the broker {}:{}; reconnecting with backoff", cfg_.host,
                         cfg_.port);
          }
          connected_ = false;
          drop_raw_locked();
          acked_.notify_all();
          break;
        case Event::kPublished:
          inflight_.erase(e.value);
          if (e.value == status_mid_) {
            status_mid_ = -1;
            acked_.notify_all();
          }
          break;
        case Event::kMessage:
          messages.push_back(std::move(e));
          break;
      }
    }
    flush_locked();
  }
  // Outside every lock: a handler may publish. handler_ is set before start() and not after.
  if (handler_) {
    for (const Event& m : messages) {
      handler_(m.topic, m.payload);
    }
  }
}

bool MosquittoClient::connected() const {
  std::lock_guard lock(mutex_);
  return connected_;
}
std::uint64_t MosquittoClient::dropped() const {
  std::lock_guard lock(mutex_);
  return outbox_.dropped();
}
std::size_t MosquittoClient::pending() const {
  std::lock_guard lock(mutex_);
  return outbox_.size() + inflight_.size();
}
std::uint64_t MosquittoClient::refused() const {
  std::lock_guard lock(mutex_);
  return refused_;
}
std::uint64_t MosquittoClient::connections() const {
  std::lock_guard lock(mutex_);
  return connections_;
}
std::uint64_t MosquittoClient::batches() const {
  std::lock_guard lock(mutex_);
  return batches_;
}
std::uint64_t MosquittoClient::batched_messages() const {
  std::lock_guard lock(mutex_);
  return batched_messages_;
}
std::uint64_t MosquittoClient::raw_deferred() const {
  std::lock_guard lock(mutex_);
  return raw_deferred_;
}
std::uint64_t MosquittoClient::raw_discarded() const {
  std::lock_guard lock(mutex_);
  return raw_discarded_;
}
int MosquittoClient::last_connack() const {
  std::lock_guard lock(mutex_);
  return last_connack_;
}

}  // namespace tb::mqtt
