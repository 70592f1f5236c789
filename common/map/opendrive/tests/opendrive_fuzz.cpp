// libFuzzer target: the OpenDRIVE importer on arbitrary text. Anything it accepts must evaluate
// without crashing anywhere on its roads; anything it refuses must be a MapError.

#include <cmath>
#include <cstdint>
#include <string_view>

#include "common/map/opendrive/reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tb::map::odr;
  try {
    const RoadNetwork net =
        parse_opendrive(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz");
    for (const Road& r : net.roads) {
      for (int i = 0; i <= 4; ++i) {
        const double s = r.length * i / 4.0;
        (void)r.surface(s, 1.0);
        (void)r.borders(r.section_index(s), s);
        (void)r.curvature(s);
      }
    }
  } catch (const MapError&) {
  }
  return 0;
}
