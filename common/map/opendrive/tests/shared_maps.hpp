#pragma once
/// @file Where the tests find the shared OpenDRIVE test maps: TESTBED_OPENDRIVE_DIR (ctest sets
/// it from the CMake cache variable of that name; benchmarks have it compiled in as
/// TB_OPENDRIVE_DIR), else shared/data/opendrive beside the clone, as in CI (TESTBED_ROOT names
/// the clone when the tests run outside it).

#include <cstdlib>
#include <filesystem>

namespace tb::map::odr::test {

inline std::filesystem::path shared_maps() {
  if (const char* dir = std::getenv("TESTBED_OPENDRIVE_DIR"); dir != nullptr && *dir != '\0')
    return dir;
#ifdef TB_OPENDRIVE_DIR
  // Benchmarks, run by hand from anywhere: the folder CMake was configured with.
  return TB_OPENDRIVE_DIR;
#endif
  const char* root = std::getenv("TESTBED_ROOT");
  return std::filesystem::path(root != nullptr ? root : ".") / ".." / "shared" / "data" /
         "opendrive";
}

}  // namespace tb::map::odr::test
