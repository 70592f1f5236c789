#pragma once
/// @file its-station as a road-side unit (issue 34): the scenario's `rsus` entry of our station
/// id makes the program an RSU — station type 15, no CAN, no LCRW — that sends its junction's
/// MAPEM and SPATEM (its-station/rsu) from the signal feed it listens to on UDP.

#include <array>
#include <cstdint>
#include <memory>
#include <string>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <nlohmann/json.hpp>

#include "common/clock/runtime.hpp"
#include "common/map/scenario_map.hpp"
#include "common/scenario/scenario.hpp"
#include "its-station/facilities/transport.hpp"
#include "its-station/rsu/rsu_service.hpp"

namespace tb::its::app {

/// The contract's default listener of an RSU.
inline constexpr const char* kDefaultSignalsUrl = "udp://0.0.0.0:4720";

/// `udp://HOST:PORT` (HOST an IPv4/IPv6 address) as an endpoint. @throws std::invalid_argument
/// naming the option and the value.
boost::asio::ip::udp::endpoint parse_signals_url(const std::string& url);

/// The RSU's services and feed listener.
class RsuMode {
 public:
  /// Builds the junction's MAPEM from the scenario's map. @throws map::odr::MapError (an unknown
  /// junction, a map without a georeference or origin) and std::invalid_argument (--signals).
  RsuMode(boost::asio::io_context& io, clock::Runtime& its_clock, facilities::MessageSender& sender,
          const scenario::Scenario& scenario, const scenario::Rsu& rsu,
          const std::string& signals_url);
  ~RsuMode();

  /// Binds the feed socket (@throws boost::system::system_error naming nothing: the caller
  /// names the endpoint) and starts MAPEM/SPATEM.
  void start();
  void stop();
  /// The status file's `rsu` object.
  nlohmann::json status() const;
  const rsu::RsuService& service() const { return *service_; }

 private:
  void receive();

  boost::asio::io_context& io_;
  const scenario::Rsu rsu_;
  boost::asio::ip::udp::endpoint listen_;
  std::unique_ptr<rsu::RsuService> service_;
  boost::asio::ip::udp::socket socket_;
  boost::asio::ip::udp::endpoint from_;
  std::array<std::uint8_t, 65536> buffer_{};
  bool running_ = false;
};

}  // namespace tb::its::app
