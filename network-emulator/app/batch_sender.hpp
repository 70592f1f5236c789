#pragma once
/// @file BatchSender: many stations' datagrams out of one unconnected UDP socket, one sendmmsg
/// per batch, with each station's faults still told apart.
///
/// At 1000 stations × 100 Hz a send() per datagram (one connected socket per feed) made the
/// system calls a large part of the emulator's cost. Here every feed is a *sink* of one
/// BatchSender; send() copies the datagram into the batch, flush() hands the batch to the
/// kernel in as few sendmmsg calls as it takes.
///
/// Faults, as a connected socket per feed had them (README, "Faults"): the socket has
/// IP_RECVERR (IPV6_RECVERR), so an ICMP error (port or host unreachable) is queued on its
/// error queue with the destination of the datagram that caused it. flush() reads that queue
/// and parks the error on every sink that sends to that destination; the sink's next send()
/// returns it instead of queueing, just as a connected socket's next send() would. A full
/// socket buffer drops one datagram (counted) and parks nothing.
///
/// The system calls sit behind BatchSocketOps so that tests script them.

#include <sys/socket.h>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <system_error>
#include <unordered_map>
#include <vector>

namespace tb::emu {

/// An IPv4 or IPv6 address and port, comparable and hashable; what the error queue names.
struct Destination {
  sockaddr_storage addr{};
  socklen_t len = 0;

  static Destination from(const sockaddr* a, socklen_t len);
  int family() const { return addr.ss_family; }
  /// Family, address and port only (sin_zero, flow info and the like are ignored).
  bool operator==(const Destination& o) const;
  std::string to_string() const;
};
struct DestinationHash {
  std::size_t operator()(const Destination& d) const;
};

/// One entry of a socket's error queue that names a destination.
struct QueuedError {
  Destination destination;  ///< where the datagram that failed was going
  std::error_code error;    ///< ee_errno: connection_refused, host_unreachable, ...
};

/// Parses one message read with recvmsg(MSG_ERRQUEUE): the destination from msg_name, the
/// error from the IP_RECVERR / IPV6_RECVERR control message. nullopt for anything else (no
/// such control message, no destination, or an entry that is not an error, like a time stamp).
std::optional<QueuedError> parse_error_queue_message(const msghdr& msg);

/// The system calls of a batch sender's socket.
class BatchSocketOps {
 public:
  virtual ~BatchSocketOps() = default;
  /// As sendmmsg(2) without blocking: sends @p msgs in order and returns how many were sent,
  /// or -errno when the first could not be sent.
  virtual int send_many(std::span<mmsghdr> msgs) = 0;
  /// Takes one entry off the socket's error queue; nullopt when it is empty. Entries that
  /// parse_error_queue_message() does not understand come back as QueuedError with no error.
  virtual std::optional<QueuedError> read_error() = 0;
};

struct BatchStats {
  std::uint64_t queued = 0;       ///< datagrams accepted by send()
  std::uint64_t sent = 0;         ///< handed to the kernel
  std::uint64_t dropped = 0;      ///< not sent: the socket buffer was full
  std::uint64_t failed = 0;       ///< not sent: an error of its own destination
  std::uint64_t late_errors = 0;  ///< error-queue entries (ICMP errors) read
  std::uint64_t calls = 0;        ///< sendmmsg calls
};

class BatchSender {
 public:
  /// @p max_batch datagrams at most per sendmmsg (the kernel takes up to 1024, UIO_MAXIOV).
  /// @p connected: the socket is connected to the one destination of all its sinks, and the
  /// datagrams go without an address (the kernel then uses the socket's cached route).
  explicit BatchSender(BatchSocketOps& ops, std::size_t max_batch = 512, bool connected = false);
  BatchSender(const BatchSender&) = delete;
  BatchSender& operator=(const BatchSender&) = delete;

  using Sink = std::size_t;
  /// A feed sending to @p to. Several sinks may share a destination; an error for it reaches
  /// all of them.
  Sink add_sink(const Destination& to);

  /// Queues a copy of @p datagram for @p sink, or returns (and forgets) the error parked on
  /// the sink since its last send; then the datagram is not sent. Flushes first when the
  /// batch is full.
  std::error_code send(Sink sink, std::span<const std::uint8_t> datagram);
  /// The parked error of @p sink, taken as send() would take it, without sending anything.
  std::error_code take_error(Sink sink);
  /// Sends what is queued, then reads the error queue.
  void flush();
  /// Reads the error queue and parks what it finds; returns how many entries it read.
  std::size_t read_errors();

  bool empty() const { return queued_.empty(); }
  const BatchStats& stats() const { return stats_; }

 private:
  struct Queued {
    Sink sink;
    std::size_t offset, size;  // in arena_
  };

  BatchSocketOps& ops_;
  std::size_t max_batch_;
  bool connected_;
  std::vector<Destination> destinations_;
  std::unordered_map<Destination, std::size_t, DestinationHash> destination_index_;
  std::vector<std::vector<Sink>> sinks_of_destination_;
  std::vector<std::size_t> destination_of_sink_;
  std::vector<std::error_code> parked_;  // per sink
  // Reused from batch to batch: no allocation per datagram once they have grown.
  std::vector<std::uint8_t> arena_;
  std::vector<Queued> queued_;
  std::vector<mmsghdr> headers_;
  std::vector<iovec> iovecs_;
  BatchStats stats_;
};

}  // namespace tb::emu
