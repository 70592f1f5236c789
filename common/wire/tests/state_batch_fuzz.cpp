// Fuzz target for the vehicle-state batch datagram (docs/wire.md): any bytes through
// decode_batch, which must not read out of bounds; whatever decodes must encode to a datagram of
// the same size that decodes to the same states (not the same bytes: unused bits of the controls
// byte are dropped), and the old single-record decoder must refuse every batch.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>
#include <vector>

#include "common/wire/vehicle_state.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> bytes(data, size);
  static std::vector<tb::wire::VehicleState> states;
  std::int64_t start = -1;
  const auto count = tb::wire::decode_batch(bytes, states, &start);
  if (!count) {
    if (!states.empty())
      std::abort();  // a refused datagram hands on no state
    return 0;
  }
  if (*count != states.size() || states.empty())
    std::abort();
  const auto again = tb::wire::encode_batch(states, start);
  std::vector<tb::wire::VehicleState> back;
  std::int64_t start_again = -1;
  if (again.size() != size || !tb::wire::decode_batch(again, back, &start_again) ||
      back != states || start_again != start)
    std::abort();
  if (tb::wire::decode(bytes))
    std::abort();  // a batch is never misread as a version-1 record
  return 0;
}
