#pragma once
/// @file An MQTT connection over libmosquitto: the station's publishers write through it, and
/// readers (sim-client's driver's view) subscribe with it.
///
/// Threading: publish() writes to the broker's socket in the caller's thread (libmosquitto
/// without its threaded mode). A thread of this class polls the socket: it reads (acknowledgements,
/// subscribed messages), keeps the connection alive, finishes a write the socket could not take
/// at once, and connects and reconnects with exponential backoff. Handing each message to a
/// network thread instead cost two thread switches, a select and a read per message, half the
/// station's CPU with 50 stations (issue 21, docs/latency.md). libmosquitto's callbacks (which it
/// calls under its own locks, in whichever thread drives it) only queue what happened; the
/// network thread applies it under this class's mutex, never from inside libmosquitto, so the
/// two sets of locks are never taken in opposite orders. publish() may be called from any
/// thread; nothing here waits for the broker.
///
/// Delivery: QoS 1 messages (warnings, DENMs) go into a bounded Outbox and are handed to
/// libmosquitto only while connected, at most max_inflight unacknowledged at a time; handed
/// messages are libmosquitto's to retransmit after a reconnect. QoS 0 messages (state, CAMs)
/// are sent only while connected and otherwise discarded: a stale position is worth nothing.
///
/// Batching: with set_flush_request(), QoS 0 messages are held and written together at flush(),
/// which the owner runs once its thread has done what one wake-up brought (its-station posts it
/// onto its io_context). A QoS 1 message first writes what is held, so that messages leave in
/// the order they were published.
///
/// QoS 0 writes: this class encodes QoS 0 PUBLISH packets itself (publish_packet.hpp) and sends
/// a batch with one send(): libmosquitto would make a write per packet plus a write of a byte to
/// its internal socket pair per publish, the largest share of a station's system calls (issue
/// 33, docs/latency.md). Bytes of two writers on one stream must never interleave inside a
/// packet, so: every libmosquitto call that may write is made under mutex_; our bytes go only
/// when libmosquitto has nothing half written (mosquitto_want_write), else through
/// mosquitto_publish behind its own; and while our bytes are half written (the socket was full)
/// the network thread finishes them before libmosquitto reads, writes or pings again. A broker
/// that takes nothing for a keepalive period loses the connection, as an unanswered ping would.
/// QoS 0 messages beyond kRawBacklogMax bytes waiting are discarded whole, never cut.
///
/// Subscriptions: the topic filters in ClientConfig::subscriptions are (re)subscribed on every
/// connection (the broker keeps no session for a clean client), and each message is handed to
/// the message handler in the network thread.

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "common/clock/clock.hpp"
#include "common/mqtt/outbox.hpp"
#include "common/mqtt/sink.hpp"

struct mosquitto;
struct mosquitto_message;

namespace tb::mqtt {

struct ClientConfig {
  std::string host = "127.0.0.1";
  int port = 1883;
  std::string client_id;  ///< empty: the broker assigns one
  std::string username;
  std::string password;
  int keepalive_s = 10;
  unsigned reconnect_min_s = 1;  ///< first retry delay; doubles up to reconnect_max_s
  unsigned reconnect_max_s = 30;
  std::size_t queue_capacity = 1000;
  std::size_t max_inflight = 20;
  /// Retained {"online":…} status with a last will; empty: none.
  std::string status_topic;
  /// When set (e.g. "its/1001/"), topics outside it are refused here with an error, as the
  /// broker's ACL would refuse them silently.
  std::string publish_prefix;
  /// Topic filters to subscribe to (with subscribe_qos) on every connection.
  std::vector<std::string> subscriptions;
  Qos subscribe_qos = Qos::kAtLeastOnce;
};

/// Called in the network thread for every message on a subscribed topic.
using MessageHandler = std::function<void(std::string_view topic, std::string_view payload)>;

class MqttError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class MosquittoClient final : public MqttSink {
 public:
  /// @throws MqttError when libmosquitto cannot make a client from @p cfg.
  MosquittoClient(const clock::Clock& clock, ClientConfig cfg);
  ~MosquittoClient() override;
  MosquittoClient(const MosquittoClient&) = delete;
  MosquittoClient& operator=(const MosquittoClient&) = delete;

  /// Sets what receives the subscribed topics' messages; call before start().
  void set_message_handler(MessageHandler handler);
  /// Starts the network thread and the first connection attempt; a broker that is down is
  /// retried in the background. @throws MqttError if the thread cannot start.
  void start();
  /// Publishes the offline status (waiting up to @p grace for its acknowledgement),
  /// disconnects and joins the network thread. Idempotent.
  void stop(std::chrono::milliseconds grace = std::chrono::milliseconds{1000});

  void publish(std::string_view topic, std::string payload, Qos qos, bool retain) override;

  /// Holds QoS 0 messages until flush(); @p request_flush is called in the publishing thread at
  /// the first message of each batch, under this class's lock: it must only arrange for flush()
  /// to run soon (post it onto the owner's loop), never call into this client. Call before
  /// start(). stop() writes what is still held.
  void set_flush_request(std::function<void()> request_flush);
  /// Writes the held messages in one corked burst (discards them when not connected, as any
  /// QoS 0 message).
  void flush();
  /// QoS 0 writes (a flush() with at least one message, or one unheld QoS 0 message while
  /// connected) and the messages in them.
  std::uint64_t batches() const;
  std::uint64_t batched_messages() const;
  /// Times the socket was full and our bytes waited for the network thread.
  std::uint64_t raw_deferred() const;
  /// QoS 0 messages discarded because kRawBacklogMax bytes were already waiting.
  std::uint64_t raw_discarded() const;

  /// How many bytes of our QoS 0 packets may wait for a broker that does not read.
  static constexpr std::size_t kRawBacklogMax = 1 << 20;

  bool connected() const;
  /// QoS 1 messages dropped because the queue overflowed while the broker was away.
  std::uint64_t dropped() const;
  /// QoS 1 messages not yet acknowledged by the broker (waiting plus in flight).
  std::size_t pending() const;
  /// Messages refused because their topic is outside publish_prefix.
  std::uint64_t refused() const;
  /// Successful CONNACKs so far.
  std::uint64_t connections() const;
  /// The last CONNACK's return code (0 accepted, 5 not authorised, …); -1 before any.
  int last_connack() const;

 private:
  static void on_connect(struct mosquitto*, void* self, int rc);
  static void on_disconnect(struct mosquitto*, void* self, int rc);
  static void on_publish(struct mosquitto*, void* self, int mid);
  static void on_message(struct mosquitto*, void* self, const struct mosquitto_message* m);
  void run();
  /// Polls the connected socket until the connection ends or stop(); the libmosquitto result.
  int serve();
  /// Wakes the network thread out of its poll (a write left over, stop()).
  void wake_network();
  void wake_if_unwritten_locked();
  void flush_locked();
  void write_held_locked();
  std::size_t raw_pending_locked() const;
  /// Sends what is encoded and unsent, as far as the socket takes it without blocking.
  void send_raw_locked();
  void drop_raw_locked();
  std::string status_payload_locked(bool online) const;

  const clock::Clock& clock_;
  ClientConfig cfg_;
  struct mosquitto* mosq_ = nullptr;
  /// What a libmosquitto callback reported, applied by apply_events() (see on_connect).
  struct Event {
    enum Kind { kConnack, kDisconnect, kPublished, kMessage } kind;
    int value;  ///< CONNACK / disconnect code, message id
    std::string topic;
    std::string payload;
  };
  void queue_event(Event e);
  /// Applies the queued events under mutex_ and hands messages to the handler outside it;
  /// called by the network thread only, never from inside libmosquitto.
  void apply_events();

  mutable std::mutex mutex_;
  std::condition_variable acked_;
  MessageHandler handler_;
  Outbox outbox_;
  std::set<int> inflight_;
  int status_mid_ = -1;
  bool connected_ = false;
  bool started_ = false;
  bool stopping_ = false;
  std::condition_variable wake_;
  std::mutex events_mutex_;  ///< a leaf: nothing is called while it is held
  std::vector<Event> events_;
  int wake_fd_ = -1;  ///< eventfd the network thread polls beside the socket
  std::thread thread_;
  std::uint64_t connections_ = 0;
  std::uint64_t refused_ = 0;
  int last_connack_ = -1;
  std::function<void()> request_flush_;
  std::vector<OutMessage> held_;  ///< QoS 0 messages waiting for flush()
  std::uint64_t batches_ = 0;
  std::uint64_t batched_messages_ = 0;
  std::string raw_;           ///< QoS 0 packets encoded here; raw_sent_ bytes of it are sent
  std::size_t raw_sent_ = 0;  ///< raw_[raw_sent_, end) waits for room in the socket
  bool raw_waiting_ = false;
  clock::SteadyTime raw_stalled_since_{};  ///< the socket's last progress while raw_waiting_
  std::uint64_t raw_deferred_ = 0;
  std::uint64_t raw_discarded_ = 0;
};

}  // namespace tb::mqtt
