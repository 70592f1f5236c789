#pragma once
/// @file A LinkLayer decorator that takes frames in only once the station knows the world's time.

#include <cstdint>

#include "common/clock/gnss_disciplined_runtime.hpp"
#include "its-station/link/link_layer.hpp"

namespace tb::its::station {

/// Until its first fix a station's ITS clock is the host's, which may lie seconds (or, with a
/// pinned start time, a year) from the world's: every timestamp it checked then — a signed
/// packet's generation time, a DENM's validity, a CAM's age — would be judged against the wrong
/// clock and refused for it. As it sends nothing before its first fix, it takes nothing in
/// either: received frames are counted and dropped until the clock is synchronised.
class TimeSyncedLink final : public link::LinkLayer {
 public:
  TimeSyncedLink(link::LinkLayer& inner, const clock::GnssDisciplinedRuntime& clock)
      : inner_(inner), clock_(clock) {}

  link::MacAddress address() const override { return inner_.address(); }
  std::error_code send(const link::MacAddress& destination, std::uint16_t ethertype,
                       std::span<const std::uint8_t> payload) override {
    return inner_.send(destination, ethertype, payload);
  }
  void set_receive_handler(link::ReceiveHandler handler) override {
    if (!handler) {
      inner_.set_receive_handler({});
      return;
    }
    inner_.set_receive_handler([this, h = std::move(handler)](const link::ReceivedFrame& f) {
      if (!clock_.synchronised()) {
        ++dropped_before_sync_;
        return;
      }
      h(f);
    });
  }
  /// Frames dropped because they came before the first fix.
  std::uint64_t dropped_before_sync() const { return dropped_before_sync_; }

 private:
  link::LinkLayer& inner_;
  const clock::GnssDisciplinedRuntime& clock_;
  std::uint64_t dropped_before_sync_ = 0;
};

}  // namespace tb::its::station
