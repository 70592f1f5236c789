#include "common/wire/signal_feed.hpp"

namespace tb::wire {

std::string_view to_string(SignalFeedError e) {
  switch (e) {
    case SignalFeedError::kBadFrame:
      return "not a valid sim-protocol frame";
    case SignalFeedError::kTruncated:
      return "shorter than its frame header says";
    case SignalFeedError::kTrailingBytes:
      return "bytes after the frame (one frame per datagram)";
    case SignalFeedError::kNotSignalStates:
      return "a frame other than SignalStates";
    case SignalFeedError::kTooLarge:
      return "larger than a UDP datagram";
  }
  return "unknown";
}

Expected<std::vector<std::uint8_t>, SignalFeedError> encode_signal_feed(
    const sim::SignalStates& states) {
  std::vector<std::uint8_t> bytes = sim::encode(states);
  if (bytes.size() > kMaxSignalFeedDatagram || states.groups.size() > sim::kMaxSignalGroupStates)
    return Unexpected{SignalFeedError::kTooLarge};
  return bytes;
}

Expected<sim::SignalStates, SignalFeedError> decode_signal_feed(
    std::span<const std::uint8_t> datagram) {
  // The server's side: SignalStates is a server → client message with its own payload bound.
  sim::FrameParser parser(sim::Sender::kServer);
  auto rest = datagram;
  const auto status = parser.parse(rest);
  if (!status)
    return Unexpected{status.error() == sim::ProtocolError::kUnknownType
                          ? SignalFeedError::kNotSignalStates
                          : SignalFeedError::kBadFrame};
  if (*status != sim::FrameParser::Status::kFrame)
    return Unexpected{SignalFeedError::kTruncated};
  if (!rest.empty())
    return Unexpected{SignalFeedError::kTrailingBytes};
  if (parser.frame().type != sim::MessageType::kSignalStates)
    return Unexpected{SignalFeedError::kNotSignalStates};
  auto message = sim::decode_server(parser.frame());
  if (!message)
    return Unexpected{SignalFeedError::kBadFrame};
  auto* states = std::get_if<sim::SignalStates>(&*message);
  if (states == nullptr)
    return Unexpected{SignalFeedError::kNotSignalStates};
  return std::move(*states);
}

}  // namespace tb::wire
