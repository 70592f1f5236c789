#pragma once
/// @file The shared medium: hands every frame a station transmits to each other station the
/// channel model lets it reach, after the model's delay. Pure logic; the I/O behind FrameSink
/// is a veth's AF_PACKET socket (veth_medium.hpp) or, in tests, a vector.

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <span>
#include <vector>

#include "common/clock/runtime.hpp"
#include "network-emulator/radio/channel.hpp"

namespace tb::emu::radio {

/// The medium's way to put a frame into one station's receiver.
class FrameSink {
 public:
  virtual ~FrameSink() = default;
  virtual void transmit(std::span<const std::uint8_t> frame) = 0;
};

/// A station-host's port (issue 33): one frame to many of the host's stations at once. The
/// medium calls it once per frame and due time with every receiver of that host that gets the
/// frame then (the port writes one TBPD frame, common/wire/pooled_delivery.hpp).
class PooledSink {
 public:
  virtual ~PooledSink() = default;
  virtual void transmit(std::span<const StationId> receivers,
                        std::span<const std::uint8_t> frame) = 0;
};

/// Sees every frame a station puts on the air, before the channel decides: the veth medium's
/// (Ethernet) and the hwsim medium's (802.11) alike. @p unix_ns is when the kernel received it
/// (CLOCK_REALTIME), or 0 where the medium does not know: then it is now.
using FrameObserver =
    std::function<void(StationId from, std::span<const std::uint8_t> frame, std::int64_t unix_ns)>;

class Medium {
 public:
  Medium(clock::Runtime& runtime, Channel& channel) : runtime_(runtime), channel_(channel) {}
  ~Medium();
  Medium(const Medium&) = delete;
  Medium& operator=(const Medium&) = delete;

  /// @p sink must outlive the medium (or detach()).
  void attach(StationId id, FrameSink& sink);
  /// @p id is a pooled station behind @p host (a station-host's port, shared by its stations).
  void attach_pooled(StationId id, PooledSink& host);
  void detach(StationId id);

  /// Range culling (on by default): a frame is offered only to the receivers within the
  /// channel's maximum range, found through the positions' spatial index (Channel::reachable)
  /// instead of deciding every pair. Off, every receiver is offered (the links beyond the
  /// range are then counted as dropped, out_of_range or below_sensitivity). Either way
  /// receivers without a position are offered, so that their links say unknown_position.
  void set_culling(bool on) { culling_ = on; }

  /// Called with every frame that comes in, before the channel decides (the trace's
  /// `medium.rx`).
  void set_frame_observer(FrameObserver o) { frame_observer_ = std::move(o); }

  /// A frame @p from put on the air. Frames with no delay are handed over before this returns;
  /// delayed ones keep their order per receiver, as a radio does not reorder (a later frame
  /// with less jitter waits for the one before it).
  /// @p unix_ns: when the kernel received it, for the observer (0: unknown).
  void on_frame(StationId from, std::span<const std::uint8_t> frame, std::int64_t unix_ns = 0);
  /// A frame a station of another node put on the air (issue 35, federation.hpp): decided per
  /// local receiver and delivered as on_frame(), but not shown to the frame observer, which
  /// federates and traces (`medium.rx`) only this node's own stations' frames.
  void on_remote_frame(StationId from, std::span<const std::uint8_t> frame);

  std::uint64_t frames_in() const { return frames_in_; }
  std::uint64_t remote_frames_in() const { return remote_frames_in_; }
  /// Per receiving station, pooled ones included.
  std::uint64_t deliveries() const { return deliveries_; }
  /// Calls of a PooledSink (each carries one or more deliveries).
  std::uint64_t pooled_transmits() const { return pooled_transmits_; }
  /// Receivers not offered a frame because they were out of range, over all frames.
  std::uint64_t culled() const { return culled_; }
  std::size_t pending() const { return timers_.size(); }

 private:
  struct Receiver {
    FrameSink* sink = nullptr;     ///< a full station's port, or
    PooledSink* pooled = nullptr;  ///< its station-host's port
    clock::SteadyTime last_due{};
  };
  /// A pooled delivery waiting to be grouped with its host's others of the same due time.
  struct PooledDelivery {
    PooledSink* host;
    clock::SteadyTime due;
    StationId to;
  };

  /// Fills offered_ with the receivers @p from's frame is offered to, in id order.
  void offer(StationId from);
  void deliver(StationId from, std::span<const std::uint8_t> frame);
  void schedule(clock::SteadyTime due, std::function<void()> fn);
  void flush_pooled(std::span<const std::uint8_t> frame, clock::SteadyTime now,
                    std::shared_ptr<const std::vector<std::uint8_t>>& copy);

  clock::Runtime& runtime_;
  Channel& channel_;
  std::map<StationId, Receiver> receivers_;
  std::set<clock::TimerId> timers_;
  FrameObserver frame_observer_;
  bool culling_ = true;
  // Reused per frame.
  std::vector<StationId> offered_;
  std::vector<StationId> reachable_;
  std::vector<PooledDelivery> pooled_;
  std::vector<StationId> group_;
  /// Receivers attached before their first position: offered every frame until they have one.
  std::vector<StationId> unplaced_;
  std::uint64_t frames_in_ = 0;
  std::uint64_t remote_frames_in_ = 0;
  std::uint64_t deliveries_ = 0;
  std::uint64_t pooled_transmits_ = 0;
  std::uint64_t culled_ = 0;
};

}  // namespace tb::emu::radio
