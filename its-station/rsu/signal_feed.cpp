#include "its-station/rsu/signal_feed.hpp"

#include <variant>

namespace tb::its::rsu {

namespace sim = wire::sim;

std::string to_string(const FeedError& e) {
  switch (e.kind) {
    case FeedError::Kind::kProtocol:
      return "malformed frame (" + std::string(sim::to_string(e.protocol)) + ")";
    case FeedError::Kind::kIncomplete:
      return "datagram shorter than its frame";
    case FeedError::Kind::kTrailingBytes:
      return "bytes after the frame (one datagram must be one frame)";
    case FeedError::Kind::kNotSignalStates:
      return "a frame that is not SignalStates (0x86)";
  }
  return "unknown";
}

Expected<sim::SignalStates, FeedError> parse_signal_datagram(
    std::span<const std::uint8_t> datagram) {
  sim::FrameParser parser(sim::Sender::kServer);
  std::span<const std::uint8_t> rest = datagram;
  const auto status = parser.parse(rest);
  if (!status)
    return Unexpected{FeedError{FeedError::Kind::kProtocol, status.error()}};
  if (*status != sim::FrameParser::Status::kFrame)
    return Unexpected{FeedError{FeedError::Kind::kIncomplete, {}}};
  if (!rest.empty())
    return Unexpected{FeedError{FeedError::Kind::kTrailingBytes, {}}};
  if (parser.frame().type != sim::MessageType::kSignalStates)
    return Unexpected{FeedError{FeedError::Kind::kNotSignalStates, {}}};
  auto msg = sim::decode_server(parser.frame());
  if (!msg)
    return Unexpected{FeedError{FeedError::Kind::kProtocol, msg.error()}};
  auto* states = std::get_if<sim::SignalStates>(&*msg);
  if (states == nullptr)
    return Unexpected{FeedError{FeedError::Kind::kNotSignalStates, {}}};
  return std::move(*states);
}

}  // namespace tb::its::rsu
