# Every dependency is a Debian 12 package installed by scripts/install-deps.
find_package(Threads REQUIRED)
find_package(nlohmann_json 3.10 REQUIRED)
find_package(spdlog REQUIRED)
find_package(fmt REQUIRED)
find_package(CLI11 REQUIRED)
find_package(Boost 1.74 REQUIRED)
find_package(OpenSSL 3.0 REQUIRED)  # its-station/security: ECDSA, SHA-256
find_package(GTest REQUIRED)
if(TESTBED_BENCHMARKS)
  find_package(benchmark REQUIRED)
endif()
find_package(PkgConfig REQUIRED)
find_package(pugixml REQUIRED)  # common/map: OpenDRIVE importer
find_package(PROJ REQUIRED)  # common/map: geoReference -> WGS84
