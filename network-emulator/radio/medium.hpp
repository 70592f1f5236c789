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
  void detach(StationId id);

  /// Called with every frame that comes in, before the channel decides (the trace's
  /// `medium.rx`).
  void set_frame_observer(FrameObserver o) { frame_observer_ = std::move(o); }

  /// A frame @p from put on the air. Frames with no delay are handed over before this returns;
  /// delayed ones keep their order per receiver, as a radio does not reorder (a later frame
  /// with less jitter waits for the one before it).
  /// @p unix_ns: when the kernel received it, for the observer (0: unknown).
  void on_frame(StationId from, std::span<const std::uint8_t> frame, std::int64_t unix_ns = 0);

  std::uint64_t frames_in() const { return frames_in_; }
  std::uint64_t deliveries() const { return deliveries_; }
  std::size_t pending() const { return timers_.size(); }

 private:
  struct Receiver {
    FrameSink* sink = nullptr;
    clock::SteadyTime last_due{};
  };

  clock::Runtime& runtime_;
  Channel& channel_;
  std::map<StationId, Receiver> receivers_;
  std::set<clock::TimerId> timers_;
  FrameObserver frame_observer_;
  std::uint64_t frames_in_ = 0;
  std::uint64_t deliveries_ = 0;
};

}  // namespace tb::emu::radio
