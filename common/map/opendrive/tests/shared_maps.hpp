#pragma once
/// @file Where the tests find the shared OpenDRIVE test maps (shared/data/opendrive beside the
/// clone, as in CI; TESTBED_ROOT names the clone when the tests run outside it).

#include <cstdlib>
#include <filesystem>

namespace tb::map::odr::test {

inline std::filesystem::path shared_maps() {
  const char* root = std::getenv("TESTBED_ROOT");
  return std::filesystem::path(root != nullptr ? root : ".") / ".." / "shared" / "data" /
         "opendrive";
}

}  // namespace tb::map::odr::test
