// Fuzz target for the sim protocol: any byte stream, from either side, through the incremental
// parser (in two slices, to exercise resumption), the decoders and the conversation checks.
// Whatever decodes must re-encode to a frame that decodes to the same message.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>

#include "common/wire/signal_feed.hpp"
#include "common/wire/sim_protocol.hpp"

namespace sim = tb::wire::sim;

namespace {

template <typename Msg, typename Decode>
void roundtrip(const Msg& m, sim::Sender from, Decode decode) {
  const auto bytes = sim::encode(m);
  sim::FrameParser p(from);
  std::span<const std::uint8_t> data(bytes);
  auto r = p.parse(data);
  if (!r || *r != sim::FrameParser::Status::kFrame || !data.empty())
    std::abort();
  auto again = decode(p.frame());
  if (!again || !(*again == m))
    std::abort();
}

void run(sim::Sender from, std::span<const std::uint8_t> bytes, std::size_t cut) {
  sim::FrameParser parser(from);
  sim::Conversation conversation;
  for (auto part : {bytes.first(cut), bytes.subspan(cut)}) {
    while (!part.empty()) {
      auto r = parser.parse(part);
      if (!r)
        return;
      if (*r == sim::FrameParser::Status::kNeedMore)
        break;
      if (from == sim::Sender::kClient) {
        auto m = sim::decode_client(parser.frame());
        if (!m)
          continue;
        roundtrip(*m, from, sim::decode_client);
        if (conversation.check(*m)) {
          if (std::holds_alternative<sim::Hello>(*m))
            conversation.on_hello();
          if (const auto* a = std::get_if<sim::Attach>(&*m); a && a->role == sim::Role::kDriver)
            conversation.on_driving(a->vehicle);
        }
      } else {
        auto m = sim::decode_server(parser.frame());
        if (m)
          roundtrip(*m, from, sim::decode_server);
      }
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2)
    return 0;
  const auto from = (data[0] & 1) ? sim::Sender::kServer : sim::Sender::kClient;
  std::span<const std::uint8_t> bytes(data + 2, size - 2);
  run(from, bytes, std::min<std::size_t>(data[1], bytes.size()));
  // The same bytes as one signal-feed datagram (issue 34): what decodes must re-encode to
  // exactly these bytes, the feed's frames being canonical.
  if (const auto states = tb::wire::decode_signal_feed(bytes)) {
    const auto again = tb::wire::encode_signal_feed(*states);
    if (!again || !std::equal(again->begin(), again->end(), bytes.begin(), bytes.end()))
      std::abort();
  }
  return 0;
}
