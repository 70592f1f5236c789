#pragma once
/// @file Where each station's GNSS and CAN feeds go (network-emulator --stations FILE).
///
///   {"stations": [{"station_id": 1001, "address": "10.20.0.2", "gnss_port": 10110,
///                  "can_port": 20000, "netns": "st1001", "can_interface": "vcan0"},
///                 {"station_id": 5001, "address": "10.20.0.9", "signal_port": 4720}]}
///
/// Stations are the scenario's vehicles and its RSUs (`rsus`, issue 34). An RSU has no CAN
/// bus; its signal feed goes to address:signal_port (default 4720, wire::kRsuSignalPort).
/// With "netns", the station's sockets are created inside that named network namespace
/// (ip netns), and "address" is as seen from inside it (127.0.0.1 reaches the station's own
/// gpsd). Without a file, every station of the scenario gets 127.0.0.1 and the ports
/// 10110 + i and 20000 + i (i = its index in the scenario), for a run on one host; the RSUs
/// follow the vehicles in that count, and RSU k (its index in `rsus`) gets signal port 4720 + k.

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "common/scenario/scenario.hpp"
#include "common/wire/signal_feed.hpp"

namespace tb::emu {

inline constexpr std::uint16_t kDefaultGnssPort = 10110;
inline constexpr std::uint16_t kDefaultCanPort = 20000;

struct StationEndpoints {
  std::uint32_t station_id = 0;
  std::string address = "127.0.0.1";
  std::uint16_t gnss_port = kDefaultGnssPort;
  std::uint16_t can_port = kDefaultCanPort;
  std::string netns;                                 ///< empty: the emulator's own namespace
  std::string can_interface = "vcan0";               ///< SocketCAN transport only
  std::uint16_t signal_port = wire::kRsuSignalPort;  ///< RSUs only
  bool rsu = false;  ///< a road-side unit of the scenario (set from it, not from the file)
};

/// A stations file that cannot be used; what() names the file, the field and the value.
class StationsConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Parses and checks @p json_text against @p scenario: every station must be one of its
/// vehicles or RSUs, none twice; CAN fields are refused for an RSU, signal_port for a vehicle.
/// @throws StationsConfigError
std::vector<StationEndpoints> parse_stations(std::string_view json_text, const std::string& file,
                                             const scenario::Scenario& scenario);
std::vector<StationEndpoints> load_stations(const std::filesystem::path& file,
                                            const scenario::Scenario& scenario);
/// The single-host defaults described above.
std::vector<StationEndpoints> default_stations(const scenario::Scenario& scenario);

}  // namespace tb::emu
