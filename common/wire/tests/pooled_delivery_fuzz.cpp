// Fuzz target for the pooled-delivery frame (TBPD, common/wire/pooled_delivery.hpp): any bytes
// through the outer-frame and payload parsers, which must not read out of bounds; whatever
// parses must rebuild (reserved byte 0) to a frame of the same size that parses to the same
// receivers and inner frame.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>
#include <vector>

#include "common/wire/pooled_delivery.hpp"

namespace {

void check_rebuild(const tb::wire::PooledDelivery& d, std::size_t payload_size) {
  if (d.receiver_count() == 0 || d.inner_frame.size() < tb::wire::kEthernetHeaderSize)
    std::abort();
  const auto ids = d.receivers();
  const auto again = tb::wire::build_pooled_delivery_frame(ids, d.inner_frame);
  if (again.size() != tb::wire::kEthernetHeaderSize + payload_size)
    std::abort();
  const auto back = tb::wire::parse_pooled_delivery_frame(again);
  if (!back || back->receivers() != ids ||
      !std::equal(back->inner_frame.begin(), back->inner_frame.end(), d.inner_frame.begin(),
                  d.inner_frame.end()) ||
      !std::equal(again.begin() + 6, again.begin() + 12, d.inner_frame.begin() + 6))
    std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> bytes(data, size);
  if (const auto d = tb::wire::parse_pooled_delivery(bytes))
    check_rebuild(*d, size);
  if (const auto f = tb::wire::parse_pooled_delivery_frame(bytes))
    check_rebuild(*f, size - tb::wire::kEthernetHeaderSize);
  return 0;
}
