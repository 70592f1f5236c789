// libFuzzer target: any datagram that reaches the federation socket must decode or be refused
// without reading outside it; what decodes must encode back to the same bytes (the reserved
// byte and flag bits aside, which the decoder ignores).

#include <cstdint>
#include <cstdlib>
#include <vector>

#include "network-emulator/radio/federation_datagram.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tb::emu::radio;
  // A copy of exactly this size, so that ASan sees a read one past the end.
  const std::vector<std::uint8_t> bytes(data, data + size);
  const auto d = decode_federation_datagram(bytes);
  if (!d)
    return 0;
  std::vector<std::uint8_t> again;
  const bool ok =
      d->kind == FederationKind::kHeartbeat
          ? encode_federation_heartbeat(d->node, d->tx_unix_ns, again)
          : encode_federated_frame(d->node, d->sender, d->has_position ? &d->position : nullptr,
                                   d->tx_unix_ns, d->frame, again);
  if (!ok)
    std::abort();
  const auto back = decode_federation_datagram(again);
  if (!back || back->node != d->node || back->tx_unix_ns != d->tx_unix_ns ||
      back->sender != d->sender || back->frame.size() != d->frame.size())
    std::abort();
  return 0;
}
