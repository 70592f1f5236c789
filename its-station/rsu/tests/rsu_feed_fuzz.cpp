// libFuzzer target: the RSU's signal-feed input (one UDP datagram, any bytes) through
// RsuService: parsed with the sim protocol's parser, and when it is a SignalStates with groups
// of intersection 100 made into a SPATEM and sent. Every SPATEM sent must decode, name
// intersection 100 and carry each of the datagram's groups of it with its state.

#include <cstdint>
#include <cstdlib>
#include <memory>
#include <span>
#include <vector>

#include "common/clock/runtime.hpp"
#include "common/wire/signal_feed.hpp"
#include "its-station/messages/spatem.hpp"
#include "its-station/rsu/rsu_service.hpp"

namespace {

namespace msg = tb::its::messages;

class Sink final : public tb::its::facilities::MessageSender {
 public:
  tb::its::facilities::SendResult send_single_hop(std::uint16_t port,
                                                  std::span<const std::uint8_t> p) override {
    if (port == tb::its::rsu::kBtpPortSpatem)
      last.assign(p.begin(), p.end());
    return tb::its::facilities::SendResult::kSent;
  }
  tb::its::facilities::SendResult send_geobroadcast(std::uint16_t,
                                                    const tb::its::facilities::GeoArea&,
                                                    std::span<const std::uint8_t>, std::uint32_t,
                                                    std::uint8_t) override {
    std::abort();  // the RSU sends single-hop only
  }
  std::vector<std::uint8_t> last;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static tb::clock::ManualRuntime rt;
  static Sink sink;
  static const auto spatem = std::make_unique<msg::Spatem>();
  tb::its::rsu::IntersectionMap map;
  map.intersection_id = 100;
  map.encoded = {0};
  tb::its::rsu::RsuService rsu(rt, sink, std::move(map));
  rsu.start();
  sink.last.clear();
  const std::span<const std::uint8_t> datagram(data, size);
  rsu.on_datagram(datagram);
  const auto parsed = tb::wire::decode_signal_feed(datagram);
  const auto& c = rsu.counters();
  if (parsed.has_value() != (c.feed_malformed == 0))
    std::abort();
  if (sink.last.empty())
    return 0;
  if (!parsed || !msg::decode(sink.last, *spatem))
    std::abort();
  const msg::IntersectionState& is = spatem->spat.intersections[0];
  if (is.id.id != 100)
    std::abort();
  std::size_t k = 0;
  for (const auto& g : parsed->groups) {
    if (g.intersection_id != 100 || k >= msg::kMovementStatesMax)
      continue;
    if (k >= is.states.size() || is.states[k].signalGroup != g.signal_group ||
        static_cast<int>(is.states[k].state_time_speed[0].eventState) != static_cast<int>(g.state))
      std::abort();
    ++k;
  }
  if (k != is.states.size())
    std::abort();
  rsu.stop();
  return 0;
}
