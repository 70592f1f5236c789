// libFuzzer target: a received frame through GN parsing, the router's receive path (checks,
// location table, duplicate detection, forwarding) and BTP dispatch. Also checks that whatever
// parses re-encodes to a packet that parses to the same headers, and that two routers sharing a
// SharedPacketParser and its SenderIndex (station-host) end where an unshared one does.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "its-station/btp/dispatcher.hpp"
#include "its-station/link/test_link.hpp"

namespace {

using namespace tb::its;

geonet::RouterConfig config_with(geonet::RouterConfig::AreaForwarding f) {
  geonet::RouterConfig c;
  c.area_forwarding = f;
  return c;
}

struct Station {
  tb::clock::ManualRuntime rt;
  link::TestLink link{{0x02, 0, 0, 0, 0, 0x01}};
  geonet::StaticPositionProvider pos;
  geonet::Router router;
  btp::Dispatcher btp{router};
  std::size_t delivered = 0;

  explicit Station(geonet::RouterConfig::AreaForwarding f) : router{rt, link, pos, config_with(f)} {
    link.keeps_sent_frames = false;
    pos.set({rt.wall_now(), 48.15, -1.6, 10.0, 90.0, true});
    for (std::uint16_t port : {btp::kPortCam, btp::kPortDenm}) {
      btp.register_port(port, [this](const btp::Indication& ind, auto payload) {
        // Touch what a real handler reads, so the sanitizers see any bad span.
        for (auto b : payload)
          delivered += b;
        delivered += ind.gn->source_position.latitude & 1;
      });
    }
  }
};

void check_round_trip(const geonet::Packet& p) {
  std::vector<std::uint8_t> out(tb::its::link::kMaxPayload + 64);
  const std::size_t n = geonet::serialize(p.basic, p.common, p.extended, p.payload, out);
  if (n == 0)
    std::abort();
  auto again = geonet::parse_packet(std::span(out).first(n));
  if (!again || again->common.type != p.common.type ||
      again->common.payload_length != p.common.payload_length ||
      !(geonet::source_position(again->extended) == geonet::source_position(p.extended)) ||
      again->basic.lifetime.encoded != p.basic.lifetime.encoded)
    std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // One router forwarding GBCs at once, one by contention (Annex F.2 and F.3).
  static Station simple{geonet::RouterConfig::AreaForwarding::kSimple};
  static Station cbf{geonet::RouterConfig::AreaForwarding::kContentionBased};
  // Two more like `simple` that share a parser, as a station-host's stations do.
  static geonet::SharedPacketParser parser;
  static Station shared_a{geonet::RouterConfig::AreaForwarding::kSimple};
  static Station shared_b{geonet::RouterConfig::AreaForwarding::kSimple};
  static const bool sharing = [] {
    shared_a.router.set_shared_parser(&parser);
    shared_b.router.set_shared_parser(&parser);
    return true;
  }();
  (void)sharing;
  const std::span<const std::uint8_t> bytes(data, size);
  if (auto p = geonet::parse_packet(bytes))
    check_round_trip(*p);
  for (Station* station : {&simple, &cbf, &shared_a, &shared_b}) {
    station->link.inject({0x02, 0, 0, 0, 0, 0x02}, tb::its::link::kBroadcastMac,
                         tb::its::link::kEtherTypeGeoNetworking, bytes, station->rt.wall_now());
    // Let time pass so that contention timers fire, the location table purges and beacons go.
    station->rt.advance(std::chrono::milliseconds{60});
    station->pos.set({station->rt.wall_now(), 48.15, -1.6, 10.0, 90.0, true});
  }
  for (const Station* station : {&shared_a, &shared_b}) {
    const auto& a = station->router.stats();
    const auto& b = simple.router.stats();
    if (a.received != b.received || a.delivered != b.delivered || a.drops != b.drops ||
        station->router.location_table().size() != simple.router.location_table().size() ||
        station->delivered != simple.delivered)
      std::abort();
  }
  return 0;
}
