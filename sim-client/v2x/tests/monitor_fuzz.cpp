// libFuzzer: MQTT messages as the broker hands them to sim-client's view (topic and payload
// from the network). The first byte picks the topic kind, the rest is the payload.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "sim-client/v2x/monitor.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static tb::client::v2x::V2xMonitor monitor;
  if (size == 0)
    return 0;
  static const char* topics[] = {
      "its/1001/app/lcrw", "its/1001/in/cam/1002", "its/1002/in/denm/1001", "its/x/app/lcrw",
      "its/1/in/denm/",    "its/1001/app/signal",  "its/1001/app/rlvw"};
  const std::string_view topic = topics[data[0] % 7];
  const std::string_view payload(reinterpret_cast<const char*>(data + 1), size - 1);
  static std::int64_t t = 0;
  t += 1'000'000;
  const tb::clock::SteadyTime now{std::chrono::nanoseconds{t}};
  monitor.on_message(topic, payload, now);
  (void)monitor.picture(now);
  return 0;
}
