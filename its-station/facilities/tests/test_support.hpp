#pragma once
// Test doubles shared by the facilities tests: a sender that records what the services hand
// to the network, and an in-memory medium that delivers it to other stations' services.

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "its-station/facilities/transport.hpp"

namespace tb::its::facilities::testing {

struct SentPacket {
  std::uint16_t port = 0;
  std::optional<GeoArea> area;  ///< set for GeoBroadcast
  std::vector<std::uint8_t> payload;
  std::uint32_t lifetime_ms = 0;
  std::uint8_t traffic_class = 0;
};

/// Records every packet; optionally forwards it (to a medium).
class RecordingSender final : public MessageSender {
 public:
  SendResult send_single_hop(std::uint16_t port, std::span<const std::uint8_t> p) override {
    packets.push_back({port, std::nullopt, {p.begin(), p.end()}, 0, 2});
    if (forward)
      forward(packets.back());
    return result;
  }
  SendResult send_geobroadcast(std::uint16_t port, const GeoArea& area,
                               std::span<const std::uint8_t> p, std::uint32_t lifetime_ms,
                               std::uint8_t traffic_class) override {
    packets.push_back({port, area, {p.begin(), p.end()}, lifetime_ms, traffic_class});
    if (forward)
      forward(packets.back());
    return result;
  }

  std::vector<SentPacket> packets;
  std::function<void(const SentPacket&)> forward;
  SendResult result = SendResult::kSent;
};

}  // namespace tb::its::facilities::testing
