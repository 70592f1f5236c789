#include "common/map/rsu_site.hpp"

#include <optional>

#include "common/map/opendrive/terrain.hpp"

namespace tb::map {

std::vector<RsuSite> rsu_sites(const std::vector<scenario::Rsu>& rsus, const ScenarioMap& map) {
  std::vector<RsuSite> out;
  std::optional<odr::Terrain> terrain;
  for (const scenario::Rsu& r : rsus) {
    RsuSite site{r.x, r.y, 0.0, 0.0};
    if (!map.flat()) {
      if (const auto at = map.locator().locate(r.x, r.y)) {
        site.ground_z = at->z;
      } else {
        if (!terrain)
          terrain.emplace(map.network());
        site.ground_z = terrain->height_at(r.x, r.y);
      }
    }
    site.antenna_z = site.ground_z + r.height_m;
    out.push_back(site);
  }
  return out;
}

}  // namespace tb::map
