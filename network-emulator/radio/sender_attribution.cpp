#include "network-emulator/radio/sender_attribution.hpp"

namespace tb::emu::radio {

std::optional<StationId> station_of_mac(std::span<const std::uint8_t, 6> mac) {
  if (mac[0] != 0x02 || mac[1] != 0x00)
    return std::nullopt;
  return StationId{mac[2]} << 24 | StationId{mac[3]} << 16 | StationId{mac[4]} << 8 |
         StationId{mac[5]};
}

void SenderAttribution::add_station_port(int ifindex, StationId id) {
  remove_station(id);
  station_of_port_[ifindex] = id;
  port_of_station_[id] = ifindex;
}

void SenderAttribution::add_pooled(int ifindex, StationId id) {
  remove_station(id);
  pooled_[id] = ifindex;
  ++host_ports_[ifindex];
}

void SenderAttribution::remove_station(StationId id) {
  if (const auto it = port_of_station_.find(id); it != port_of_station_.end()) {
    station_of_port_.erase(it->second);
    port_of_station_.erase(it);
  }
  if (const auto it = pooled_.find(id); it != pooled_.end()) {
    if (--host_ports_[it->second] == 0)
      host_ports_.erase(it->second);
    pooled_.erase(it);
  }
}

std::optional<StationId> SenderAttribution::peek_sender(int ifindex,
                                                        std::span<const std::uint8_t> frame) const {
  const auto port = station_of_port_.find(ifindex);
  const bool host = port == station_of_port_.end() && host_ports_.contains(ifindex);
  if (port == station_of_port_.end() && !host)
    return std::nullopt;
  if (frame.size() >= 12) {
    if (const auto id = station_of_mac(frame.subspan<6, 6>());
        id && (pooled_.contains(*id) || port_of_station_.contains(*id)))
      return id;
  }
  if (!host)
    return port->second;
  return std::nullopt;
}

std::optional<StationId> SenderAttribution::sender(int ifindex,
                                                   std::span<const std::uint8_t> frame) {
  const auto id = peek_sender(ifindex, frame);
  if (!id && host_ports_.contains(ifindex))
    ++unknown_sender_;
  return id;
}

}  // namespace tb::emu::radio
