#include "its-station/app/rsu_mode.hpp"

#include <stdexcept>

#include <spdlog/spdlog.h>
#include <boost/asio/ip/address.hpp>

#include "common/trace/tracer.hpp"
#include "its-station/rsu/mapem_builder.hpp"

namespace tb::its::app {

namespace asio = boost::asio;

asio::ip::udp::endpoint parse_signals_url(const std::string& url) {
  const std::string scheme = "udp://";
  auto bad = [&](const std::string& why) {
    return std::invalid_argument("--signals '" + url + "': " + why +
                                 " (expected udp://HOST:PORT, e.g. " + kDefaultSignalsUrl + ")");
  };
  if (url.rfind(scheme, 0) != 0)
    throw bad("not a udp:// address");
  const std::string rest = url.substr(scheme.size());
  const auto colon = rest.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == rest.size())
    throw bad("no HOST:PORT");
  std::string host = rest.substr(0, colon);
  if (host.size() > 2 && host.front() == '[' && host.back() == ']')
    host = host.substr(1, host.size() - 2);
  boost::system::error_code ec;
  const auto address = asio::ip::make_address(host, ec);
  if (ec)
    throw bad("'" + host + "' is not an IP address");
  const std::string port_text = rest.substr(colon + 1);
  std::size_t used = 0;
  unsigned long port = 0;
  try {
    port = std::stoul(port_text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != port_text.size() || port == 0 || port > 65535)
    throw bad("port '" + port_text + "' is not 1..65535");
  return {address, static_cast<unsigned short>(port)};
}

namespace {

rsu::IntersectionMap build_map(const scenario::Scenario& scenario, const scenario::Rsu& rsu) {
  const map::ScenarioMap m(scenario);
  rsu::IntersectionMap built =
      rsu::MapemBuilder(m.network(), m.signals(), m.georeferencing()).build(rsu.junction);
  spdlog::info("rsu {}: MAPEM of junction {} (intersection {}, revision {}): {} lanes, {} bytes",
               rsu.id, rsu.junction, built.intersection_id, unsigned{built.revision},
               built.lanes.size(), built.encoded.size());
  return built;
}

}  // namespace

RsuMode::RsuMode(asio::io_context& io, clock::Runtime& its_clock, facilities::MessageSender& sender,
                 const scenario::Scenario& scenario, const scenario::Rsu& rsu,
                 const std::string& signals_url)
    : io_(io),
      rsu_(rsu),
      listen_(parse_signals_url(signals_url)),
      service_(std::make_unique<rsu::RsuService>(its_clock, sender, build_map(scenario, rsu))),
      socket_(io) {
  service_->set_sent_listener([station = rsu.station_id](std::uint16_t port, bool on_change,
                                                         std::span<const std::uint8_t> bytes) {
    // The SPATEM's leg of the latency chain (docs/latency.md): datagram in → on the air.
    if (port == rsu::kBtpPortSpatem)
      trace::global().record(
          "its.spatem_tx",
          {{"station", station}, {"on_change", on_change}, {"bytes", bytes.size()}});
    else
      trace::global().record("its.mapem_tx", {{"station", station}, {"bytes", bytes.size()}});
  });
}

RsuMode::~RsuMode() {
  stop();
}

void RsuMode::start() {
  socket_.open(listen_.protocol());
  socket_.set_option(asio::socket_base::reuse_address(true));
  socket_.bind(listen_);
  running_ = true;
  spdlog::info(
      "rsu {}: signal feed on udp {}:{}, stale after 2 s; MAPEM 1 Hz, SPATEM 10 Hz "
      "and on change",
      rsu_.id, listen_.address().to_string(), listen_.port());
  service_->start();
  receive();
}

void RsuMode::stop() {
  if (!running_)
    return;
  running_ = false;
  service_->stop();
  boost::system::error_code ec;
  socket_.close(ec);
}

void RsuMode::receive() {
  socket_.async_receive_from(
      asio::buffer(buffer_), from_, [this](const boost::system::error_code& ec, std::size_t n) {
        if (!running_ || ec == asio::error::operation_aborted)
          return;
        if (!ec) {
          trace::global().record("its.signal_feed_rx",
                                 {{"station", rsu_.station_id}, {"bytes", n}});
          service_->on_datagram(std::span<const std::uint8_t>(buffer_.data(), n));
        }
        receive();
      });
}

nlohmann::json RsuMode::status() const {
  const auto& c = service_->counters();
  nlohmann::json j{{"id", rsu_.id},
                   {"junction", rsu_.junction},
                   {"intersection_id", service_->map().intersection_id},
                   {"revision", service_->map().revision},
                   {"mapem_sent", c.mapem_sent},
                   {"spatem_sent", c.spatem_sent},
                   {"spatem_on_change", c.spatem_on_change},
                   {"spatem_stale", c.spatem_stale},
                   {"feed_datagrams", c.feed_datagrams},
                   {"feed_malformed", c.feed_malformed},
                   {"feed_foreign", c.feed_foreign},
                   {"send_errors", c.send_errors}};
  const auto age = service_->last_feed_age_ms();
  j["last_feed_age_ms"] = age ? nlohmann::json(*age) : nlohmann::json(nullptr);
  return j;
}

}  // namespace tb::its::app
