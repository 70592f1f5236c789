#include "its-station/link/test_link.hpp"

namespace tb::its::link {

std::error_code TestLink::send(const MacAddress& destination, std::uint16_t ethertype,
                               std::span<const std::uint8_t> payload) {
  if (send_error_)
    return send_error_;
  if (payload.size() > kMaxPayload)
    return std::make_error_code(std::errc::message_size);
  SentFrame frame{destination, ethertype, {payload.begin(), payload.end()}};
  if (observer_)
    observer_(frame);
  if (keeps_sent_frames)
    sent_.push_back(std::move(frame));
  return {};
}

void TestLink::inject(const MacAddress& source, const MacAddress& destination,
                      std::uint16_t ethertype, std::span<const std::uint8_t> payload,
                      clock::WallTime rx_time) {
  if (!handler_)
    return;
  handler_(ReceivedFrame{source, destination, ethertype, payload, rx_time});
}

}  // namespace tb::its::link
