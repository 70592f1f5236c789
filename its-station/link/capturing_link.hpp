#pragma once
/// @file A LinkLayer decorator that records every frame sent and received to a pcap file, so
/// that a station's traffic can be inspected with Wireshark without a capture on the interface.

#include "common/clock/clock.hpp"
#include "its-station/link/link_layer.hpp"
#include "its-station/link/pcap_writer.hpp"

namespace tb::its::link {

class CapturingLink final : public LinkLayer {
 public:
  /// Sent frames are stamped with @p clock's wall time, received ones with their rx_time.
  CapturingLink(LinkLayer& inner, PcapWriter& pcap, const clock::Clock& clock)
      : inner_(inner), pcap_(pcap), clock_(clock) {}

  MacAddress address() const override { return inner_.address(); }
  std::error_code send(const MacAddress& destination, std::uint16_t ethertype,
                       std::span<const std::uint8_t> payload) override {
    const std::error_code ec = inner_.send(destination, ethertype, payload);
    if (!ec)
      pcap_.write(clock_.wall_now(), destination, inner_.address(), ethertype, payload);
    return ec;
  }
  void set_receive_handler(ReceiveHandler handler) override {
    if (!handler) {
      inner_.set_receive_handler({});
      return;
    }
    inner_.set_receive_handler([this, h = std::move(handler)](const ReceivedFrame& f) {
      pcap_.write(f.rx_time, f.destination, f.source, f.ethertype, f.payload);
      h(f);
    });
  }

 private:
  LinkLayer& inner_;
  PcapWriter& pcap_;
  const clock::Clock& clock_;
};

}  // namespace tb::its::link
