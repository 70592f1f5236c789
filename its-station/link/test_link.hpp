#pragma once
/// @file A LinkLayer test double: records what is sent, lets a test inject received frames.

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "its-station/link/link_layer.hpp"

namespace tb::its::link {

class TestLink final : public LinkLayer {
 public:
  struct SentFrame {
    MacAddress destination;
    std::uint16_t ethertype;
    std::vector<std::uint8_t> payload;
  };
  /// Called for every sent frame after it is recorded (a fake medium hooks in here).
  using SendObserver = std::function<void(const SentFrame&)>;

  explicit TestLink(MacAddress address) : address_(address) {}

  MacAddress address() const override { return address_; }
  std::error_code send(const MacAddress& destination, std::uint16_t ethertype,
                       std::span<const std::uint8_t> payload) override;
  void set_receive_handler(ReceiveHandler handler) override { handler_ = std::move(handler); }

  /// Delivers a frame to the handler as if the kernel had received it at @p rx_time.
  void inject(const MacAddress& source, const MacAddress& destination, std::uint16_t ethertype,
              std::span<const std::uint8_t> payload, clock::WallTime rx_time);

  void set_send_observer(SendObserver observer) { observer_ = std::move(observer); }
  /// Makes send() fail with @p error (e.g. to test how a router reports it); {} restores.
  void fail_sends_with(std::error_code error) { send_error_ = error; }

  std::vector<SentFrame>& sent() { return sent_; }
  bool keeps_sent_frames = true;

 private:
  MacAddress address_;
  ReceiveHandler handler_;
  SendObserver observer_;
  std::error_code send_error_;
  std::vector<SentFrame> sent_;
};

}  // namespace tb::its::link
