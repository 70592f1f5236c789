// its-gn-probe: sends and receives GeoNetworking/BTP-B packets on a station's radio interface
// with the stack of its_link/its_geonet/its_btp. For checking a radio (hwsim in OCB mode or the
// veth stand-in) end to end, in tests and by hand. Received packets are printed as JSON lines.
// With --cam it is a minimal ITS station of its own (GN, BTP, a CAM of a fixed position, no CA
// service rules, no LDM): the "bring your own stack" test runs it in a vehicle's place.
// With --at-cert/--at-key/--trust/--aa it signs what it sends and verifies what it receives
// (TS 103 097, `signed` mode: unverified packets are dropped) with certificate files another
// stack would be given (its-pki export), and then dates the security and GN times from GNSS
// time: the NMEA of --nmea-port (the station's feed), as every station must; its "ready" line
// then comes with the first fix, since before it the probe could verify nothing.

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <boost/asio/signal_set.hpp>
#include <nlohmann/json.hpp>

#include "common/clock/asio_runtime.hpp"
#include "common/clock/gnss_disciplined_runtime.hpp"
#include "common/util/bytes.hpp"
#include "its-station/btp/dispatcher.hpp"
#include "its-station/link/capturing_link.hpp"
#include "its-station/link/packet_socket_link.hpp"
#include "its-station/messages/cam.hpp"
#include "its-station/security/pki_files.hpp"
#include "its-station/security/security_entity.hpp"

namespace {

using namespace tb::its;
using json = nlohmann::json;

constexpr int kExitLinkError = 1;
constexpr int kExitBadArguments = 2;
constexpr int kExitNotEnoughReceived = 3;

struct Options {
  std::string interface = "wlan0";
  std::vector<double> position;  // lat, lon
  double speed_mps = 0.0;
  double heading_deg = 0.0;
  std::string send = "none";
  std::vector<double> area;  // lat, lon, radius
  int hops = 10;
  std::uint16_t port = btp::kPortCam;
  int interval_ms = 100;
  int count = 0;
  int receive_count = 0;
  double duration_s = 0.0;
  std::string pcap;
  int station_type = static_cast<int>(geonet::StationType::kPassengerCar);
  std::int64_t cam_station_id = -1;  // -1: the payload is a sequence number, not a CAM
  // Security (all four or none): the AT and its key, the trusted root, the AT's AA.
  std::string at_cert;
  std::string at_key;
  std::string trust;
  std::string aa;
  std::uint16_t nmea_port = 10110;
};

/// The UTC time of an NMEA 0183 RMC sentence (`$--RMC,hhmmss.ss,A,...,ddmmyy,...*hh`) with a
/// valid fix and checksum; nothing for any other sentence.
std::optional<tb::clock::WallTime> rmc_time(std::string_view line) {
  while (!line.empty() && (line.back() == '\r' || line.back() == '\n'))
    line.remove_suffix(1);
  const auto star = line.rfind('*');
  if (line.size() < 7 || line[0] != '$' || line.substr(3, 4) != "RMC," ||
      star == std::string_view::npos || star + 3 != line.size())
    return std::nullopt;
  unsigned sum = 0;
  for (char c : line.substr(1, star - 1))
    sum ^= static_cast<unsigned char>(c);
  const std::string given(line.substr(star + 1));
  char* end = nullptr;
  if (std::strtoul(given.c_str(), &end, 16) != sum || end != given.c_str() + given.size())
    return std::nullopt;
  std::vector<std::string_view> f;
  for (std::size_t at = 0; at <= star;) {
    const auto comma = std::min(line.find(',', at), star);
    f.push_back(line.substr(at, comma - at));
    at = comma + 1;
  }
  if (f.size() < 10 || f[2] != "A" || f[1].size() < 6 || f[9].size() != 6)
    return std::nullopt;
  auto num = [](std::string_view v) {
    int n = 0;
    for (char c : v) {
      if (c < '0' || c > '9')
        return -1;
      n = n * 10 + (c - '0');
    }
    return n;
  };
  const int hh = num(f[1].substr(0, 2)), mi = num(f[1].substr(2, 2)), ss = num(f[1].substr(4, 2));
  const int dd = num(f[9].substr(0, 2)), mo = num(f[9].substr(2, 2)), yy = num(f[9].substr(4, 2));
  double fraction = 0.0;  // hhmmss.ss: the digits after the point
  if (f[1].size() > 7 && f[1][6] == '.') {
    double scale = 0.1;
    for (char c : f[1].substr(7)) {
      if (c < '0' || c > '9')
        return std::nullopt;
      fraction += (c - '0') * scale;
      scale /= 10;
    }
  }
  const std::chrono::year_month_day date{std::chrono::year{2000 + yy},
                                         std::chrono::month{static_cast<unsigned>(mo)},
                                         std::chrono::day{static_cast<unsigned>(dd)}};
  if (hh < 0 || hh > 23 || mi < 0 || mi > 59 || ss < 0 || ss > 59 || dd < 0 || mo < 0 || yy < 0 ||
      !date.ok())
    return std::nullopt;
  const auto t = std::chrono::sys_days{date} + std::chrono::hours{hh} + std::chrono::minutes{mi} +
                 std::chrono::seconds{ss} + std::chrono::microseconds{std::llround(fraction * 1e6)};
  return tb::clock::WallTime{
      std::chrono::duration_cast<tb::clock::WallClock::duration>(t.time_since_epoch())};
}

/// The security entity of the certificate files in @p o (TS 103 097: sign with the AT, verify
/// under the root through the AA); errors name the file.
std::unique_ptr<security::SecurityEntity> make_security(const Options& o) {
  namespace sec = security;
  sec::Certificate at = sec::read_certificate(o.at_cert);
  sec::Certificate root = sec::read_certificate(o.trust);
  sec::Certificate aa = sec::read_certificate(o.aa);
  sec::EcKey key;
  try {
    key = sec::EcKey::load_private_pem(o.at_key);
  } catch (const sec::CryptoError& e) {
    throw sec::PkiFileError(e.what());
  }
  if (at.tbs.verify_key.point != key.public_point())
    throw sec::PkiFileError(o.at_key + ": not the key of " + o.at_cert);
  sec::Verifier verifier({root});
  // The chain now, its validity per packet on the GNSS clock (as its-station does).
  const auto checked =
      verifier.add_authority(aa, static_cast<sec::Time64>(aa.tbs.validity.start) * 1'000'000);
  if (checked != sec::VerifyResult::kOk)
    throw sec::PkiFileError(o.aa + ": does not verify under " + o.trust + ": " +
                            std::string(sec::to_string(checked)));
  return std::make_unique<sec::SecurityEntity>(sec::SecurityMode::kSigned,
                                               sec::Signer(std::move(at), std::move(key), aa),
                                               std::move(verifier));
}

/// ms since 2004-01-01T00:00:00 UTC (CDD TimestampIts, V1.3.1: UTC) of @p t.
std::int64_t timestamp_its(tb::clock::WallTime t) {
  return tb::clock::to_unix_ns(t) / 1'000'000 - 1'072'915'200'000;
}

/// A CAM of a station standing at @p o.position with @p o.speed_mps and @p o.heading_deg, the
/// fields the probe does not know unavailable.
messages::Cam probe_cam(const Options& o, tb::clock::WallTime now) {
  messages::Cam cam;
  cam.header.stationID = static_cast<messages::StationID>(o.cam_station_id);
  cam.cam.generationDeltaTime =
      static_cast<messages::GenerationDeltaTime>(timestamp_its(now) % 65536);
  auto& p = cam.cam.camParameters;
  p.basicContainer.stationType = static_cast<messages::StationType>(o.station_type);
  p.basicContainer.referencePosition.latitude =
      static_cast<messages::Latitude>(std::lround(o.position[0] * 1e7));
  p.basicContainer.referencePosition.longitude =
      static_cast<messages::Longitude>(std::lround(o.position[1] * 1e7));
  auto& hf = *messages::vehicle_hf(p);
  hf.heading.headingValue = static_cast<messages::HeadingValue>(
      std::lround(std::fmod(std::fmod(o.heading_deg, 360.0) + 360.0, 360.0) * 10.0) % 3600);
  hf.speed.speedValue =
      static_cast<messages::SpeedValue>(std::clamp(std::lround(o.speed_mps * 100.0), 0L, 16382L));
  return cam;
}

void print(const json& j) {
  std::cout << j.dump() << std::endl;
}

}  // namespace

int main(int argc, char** argv) {
  spdlog::set_default_logger(spdlog::stderr_color_mt("gn-probe"));
  Options o;
  CLI::App app{"Send and receive GeoNetworking/BTP-B packets on a radio interface"};
  app.add_option("--interface", o.interface, "radio interface")->capture_default_str();
  app.add_option("--position", o.position, "own position: LAT LON (degrees)")->expected(2);
  app.add_option("--speed", o.speed_mps, "own speed, m/s");
  app.add_option("--heading", o.heading_deg, "own heading, degrees clockwise from north");
  app.add_option("--send", o.send, "what to send")
      ->check(CLI::IsMember({"none", "shb", "tsb", "gbc"}))
      ->capture_default_str();
  app.add_option("--area", o.area, "GBC destination circle: LAT LON RADIUS_M")->expected(3);
  app.add_option("--hops", o.hops, "TSB/GBC maximum hop limit")->check(CLI::Range(1, 255));
  app.add_option("--port", o.port, "BTP-B port to send to and listen on")->capture_default_str();
  app.add_option("--interval-ms", o.interval_ms, "time between sent packets")
      ->check(CLI::Range(1, 3'600'000));
  app.add_option("--count", o.count, "packets to send (0: until the end)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--receive-count", o.receive_count,
                 "stop once this many packets were received (exit 3 if the time runs out first)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--duration-s", o.duration_s, "stop after this long (0: no limit)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--pcap", o.pcap, "write sent and received frames to this pcap file");
  app.add_option("--station-type", o.station_type, "GN address station type (5 = car)")
      ->check(CLI::Range(0, 31));
  app.add_option("--cam", o.cam_station_id,
                 "send CAMs of this station ID (UPER, EN 302 637-2) as the payload instead of a "
                 "sequence number, and print the station ID of every CAM received")
      ->check(CLI::Range(std::int64_t{0}, std::int64_t{4294967295}));
  auto* at_cert = app.add_option("--at-cert", o.at_cert,
                                 "sign with this AT (COER certificate file, its-pki export)");
  auto* at_key = app.add_option("--at-key", o.at_key, "the AT's private key (PEM)");
  auto* trust = app.add_option("--trust", o.trust, "trusted root certificate (COER file)");
  auto* aa = app.add_option("--aa", o.aa, "the AA certificate (COER file) of our AT");
  at_cert->needs(at_key, trust, aa);
  at_key->needs(at_cert);
  trust->needs(at_cert);
  aa->needs(at_cert);
  app.add_option("--nmea-port", o.nmea_port,
                 "UDP port of the station's NMEA feed: when signing, security and GN times are "
                 "GNSS time, and nothing is sent before the first fix")
      ->capture_default_str();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : kExitBadArguments;
  }
  if (o.send != "none" && o.position.empty()) {
    spdlog::error("--send {} needs --position LAT LON (GN packets carry the sender's position)",
                  o.send);
    return kExitBadArguments;
  }
  if (o.send == "gbc" && o.area.empty()) {
    spdlog::error("--send gbc needs --area LAT LON RADIUS_M");
    return kExitBadArguments;
  }
  if (!o.position.empty() && (std::abs(o.position[0]) > 90 || std::abs(o.position[1]) > 180)) {
    spdlog::error("--position {} {} is not on the globe", o.position[0], o.position[1]);
    return kExitBadArguments;
  }

  boost::asio::io_context io;
  tb::clock::AsioRuntime rt{io};
  const bool secured = !o.at_cert.empty();
  std::unique_ptr<security::SecurityEntity> security;
  if (secured) {
    try {
      security = make_security(o);
    } catch (const std::exception& e) {  // PkiFileError, CryptoError: they name the file
      spdlog::error("security: {}", e.what());
      return kExitBadArguments;
    }
  }
  // The ITS clock: GNSS time from the NMEA feed when signing (generationTime, certificate
  // validity and GN timestamps on the world's clock), else the host's.
  tb::clock::GnssDisciplinedRuntime its_clock{rt};
  boost::asio::ip::udp::socket nmea{io};
  std::array<char, 4096> nmea_buffer{};
  std::function<void()> on_first_fix;
  std::function<void()> read_nmea = [&] {
    nmea.async_receive(boost::asio::buffer(nmea_buffer),
                       [&](const boost::system::error_code& ec, std::size_t n) {
                         if (ec)
                           return;
                         std::string_view text(nmea_buffer.data(), n);
                         for (std::size_t at = 0; at < text.size();) {
                           const auto end = std::min(text.find('\n', at), text.size());
                           if (const auto t = rmc_time(text.substr(at, end - at))) {
                             const bool first = !its_clock.synchronised();
                             its_clock.on_fix(*t);
                             if (first) {
                               spdlog::info("ITS clock: on GNSS time from the first fix");
                               if (on_first_fix)
                                 on_first_fix();
                             }
                           }
                           at = end + 1;
                         }
                         read_nmea();
                       });
  };
  if (secured) {
    boost::system::error_code ec;
    nmea.open(boost::asio::ip::udp::v4(), ec);
    if (!ec)
      nmea.bind({boost::asio::ip::udp::v4(), o.nmea_port}, ec);
    if (ec) {
      spdlog::error("NMEA on UDP {}: {}", o.nmea_port, ec.message());
      return kExitLinkError;
    }
    read_nmea();
  }
  tb::clock::Runtime& clock = secured ? static_cast<tb::clock::Runtime&>(its_clock) : rt;
  auto opened = link::PacketSocketLink::open(io, o.interface);
  if (!opened) {
    spdlog::error("{}", opened.error().message());
    return kExitLinkError;
  }
  std::unique_ptr<link::PacketSocketLink> socket = std::move(*opened);
  spdlog::info("link: {} {} driver '{}' ({})", o.interface, link::to_string(socket->address()),
               socket->driver(),
               socket->driver() == "veth" ? "veth stand-in for the radio" : "radio interface");

  link::LinkLayer* link = socket.get();
  std::optional<link::PcapWriter> pcap;
  std::unique_ptr<link::CapturingLink> capture;
  if (!o.pcap.empty()) {
    auto w = link::PcapWriter::create(o.pcap);
    if (!w) {
      spdlog::error("{}", w.error());
      return kExitBadArguments;
    }
    pcap.emplace(std::move(*w));
    capture = std::make_unique<link::CapturingLink>(*socket, *pcap, rt);
    link = capture.get();
  }

  geonet::StaticPositionProvider position;
  // A fixed position, stamped now: re-stamped every 100 ms as a 10 Hz receiver would, and
  // before each packet, since receivers take a single-hop packet whose fix is not newer than
  // the last one's for a duplicate (EN 302 636-4-1 Annex A.3).
  auto stamp = [&] {
    // Signing, no position before GNSS time: a beacon dated on the host's clock would be out of
    // the others' generation-time window.
    if (!o.position.empty() && !(secured && !its_clock.synchronised()))
      position.set(
          {clock.wall_now(), o.position[0], o.position[1], o.speed_mps, o.heading_deg, true});
  };
  std::function<void()> refresh = [&] {
    stamp();
    rt.schedule_in(std::chrono::milliseconds{100}, refresh);
  };
  refresh();

  geonet::RouterConfig config;
  config.station_type = static_cast<geonet::StationType>(o.station_type);
  geonet::Router router{clock, *link, position, config};
  if (security) {
    router.set_security(security.get());
    spdlog::info("security: signed, AT {} under {} and {}", o.at_cert, o.aa, o.trust);
  }
  btp::Dispatcher btp{router};

  int sent = 0;
  int received = 0;
  const bool sending = o.send != "none";
  auto finished = [&] {
    const bool sent_all = !sending || (o.count > 0 && sent >= o.count);
    const bool received_all = o.receive_count == 0 || received >= o.receive_count;
    // With no count on either side, only the duration or a signal ends the run.
    const bool bounded = (sending && o.count > 0) || o.receive_count > 0;
    return bounded && sent_all && received_all;
  };

  btp.register_port(o.port, [&](const btp::Indication& ind, std::span<const std::uint8_t> p) {
    ++received;
    tb::ByteReader r{p};
    const auto seq = r.be<std::uint32_t>();
    const auto& gn = *ind.gn;
    json cam_id = nullptr;
    if (o.cam_station_id >= 0)
      if (const auto cam = messages::decode_cam(p))
        cam_id = cam->header.stationID;
    print({{"event", "rx"},
           {"cam_station_id", cam_id},
           {"type", geonet::to_string(gn.packet_type)},
           {"source", link::to_string(gn.source.mid)},
           {"sender", link::to_string(gn.sender)},
           {"port", ind.destination_port},
           {"seq", r.ok() ? json(seq) : json(nullptr)},
           {"length", p.size()},
           {"rhl", gn.remaining_hop_limit},
           {"latitude", geonet::to_degrees(gn.source_position.latitude)},
           {"longitude", geonet::to_degrees(gn.source_position.longitude)},
           {"remaining_lifetime_ms",
            std::chrono::duration_cast<std::chrono::milliseconds>(gn.remaining_lifetime).count()},
           {"rx_time_ns", tb::clock::to_unix_ns(gn.rx_time)}});
    if (finished())
      io.stop();
  });

  geonet::DataRequest request = geonet::DataRequest::single_hop();
  if (o.send == "tsb")
    request = geonet::DataRequest::topologically_scoped(static_cast<std::uint8_t>(o.hops));
  if (o.send == "gbc")
    request = geonet::DataRequest::geo_broadcast(
        geonet::make_geo_area(geonet::AreaShape::kCircle, {o.area[0], o.area[1]}, o.area[2]),
        static_cast<std::uint8_t>(o.hops));
  std::function<void()> send_next = [&] {
    if (secured && !its_clock.synchronised()) {
      // No world time yet: a generationTime on the host's clock would be out of the others'
      // window (the world's epoch may be anything).
      rt.schedule_in(std::chrono::milliseconds{o.interval_ms}, send_next);
      return;
    }
    std::array<std::uint8_t, messages::kCamMaxEncodedSize> payload{};
    std::size_t length = 8;
    if (o.cam_station_id >= 0) {
      const auto n = messages::encode(probe_cam(o, clock.wall_now()), payload);
      if (!n) {
        spdlog::error("cannot encode the CAM: {}", asn1::to_string(n.error()));
        io.stop();
        return;
      }
      length = *n;
    } else {
      tb::ByteWriter w{std::span(payload).first(8)};
      w.be<std::uint32_t>(static_cast<std::uint32_t>(sent));
    }
    stamp();
    const auto confirm = btp.send_b(request, o.port, 0, std::span(payload).first(length));
    print({{"event", "tx"}, {"seq", sent}, {"confirm", geonet::to_string(confirm)}});
    ++sent;
    if (finished()) {
      io.stop();
      return;
    }
    if (o.count == 0 || sent < o.count)
      rt.schedule_in(std::chrono::milliseconds{o.interval_ms}, send_next);
  };
  if (sending)
    rt.schedule_in(std::chrono::milliseconds{0}, send_next);
  if (o.duration_s > 0)
    rt.schedule_in(std::chrono::duration_cast<tb::clock::Duration>(
                       std::chrono::duration<double>{o.duration_s}),
                   [&] { io.stop(); });
  boost::asio::signal_set signals{io, SIGINT, SIGTERM};
  signals.async_wait([&](const boost::system::error_code& ec, int) {
    if (!ec)
      io.stop();
  });

  // Signing, a receiver is ready once it is on GNSS time: before that every packet's
  // generationTime would be judged against the host's clock and refused (a sender waits anyway).
  const auto ready = [&] {
    print({{"event", "ready"},
           {"interface", o.interface},
           {"address", link::to_string(socket->address())}});
  };
  if (secured)
    on_first_fix = ready;
  else
    ready();
  io.run();

  json drops = json::object();
  for (std::size_t i = 0; i < static_cast<std::size_t>(geonet::DropReason::kCount); ++i) {
    if (router.stats().drops[i] > 0)
      drops[geonet::to_string(static_cast<geonet::DropReason>(i))] = router.stats().drops[i];
  }
  json summary{{"event", "summary"},
               {"sent", sent},
               {"received", received},
               {"beacons_sent", router.stats().beacons_sent},
               {"forwarded", router.stats().forwarded},
               {"drops", drops}};
  if (security) {
    json verify = json::object();
    for (std::size_t i = 0; i < static_cast<std::size_t>(security::VerifyResult::kCount); ++i)
      if (const auto n = security->verifier().counts()[i]; n > 0)
        verify[std::string(security::to_string(static_cast<security::VerifyResult>(i)))] = n;
    summary["security"] = {{"mode", "signed"}, {"verify", verify}};
  }
  print(summary);
  if (pcap)
    pcap->flush();
  if (o.receive_count > 0 && received < o.receive_count) {
    spdlog::error("received {} of {} packets before the time ran out", received, o.receive_count);
    return kExitNotEnoughReceived;
  }
  return 0;
}
