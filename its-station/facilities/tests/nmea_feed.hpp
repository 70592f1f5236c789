#pragma once
// NMEA epochs for tests that feed a real gpsd: RMC + GGA + GSA in one datagram, every sentence
// with the same time (gpsd ends a cycle when the time changes; REFERENCES.md).

#include <chrono>
#include <cmath>
#include <ctime>
#include <string>

#include <fmt/format.h>

#include "common/clock/clock.hpp"

namespace tb::its::facilities::testing {

inline std::string nmea_sentence(const std::string& body) {
  unsigned cs = 0;
  for (char c : body)
    cs ^= static_cast<unsigned char>(c);
  return fmt::format("${}*{:02X}\r\n", body, cs);
}

/// ddmm.mmmmmm (latitude, 2 degree digits) or dddmm.mmmmmm (longitude, 3).
inline std::string nmea_angle(double deg, int deg_digits) {
  const double a = std::abs(deg);
  const int d = static_cast<int>(a);
  return fmt::format("{:0{}d}{:09.6f}", d, deg_digits, (a - d) * 60.0);
}

struct NmeaEpoch {
  clock::WallTime time;  ///< truncated to the 10 ms NMEA carries
  std::string datagram;
};

/// One epoch at @p t: position (northern/eastern hemisphere), speed over ground and course;
/// HDOP 0.9 with 9 satellites, altitude 500 m MSL, geoid separation 47 m.
inline NmeaEpoch nmea_epoch(clock::WallTime t, double lat, double lon, double speed_mps,
                            double course_deg) {
  NmeaEpoch e;
  const auto ms =
      std::chrono::duration_cast<std::chrono::milliseconds>(t.time_since_epoch()).count();
  e.time = clock::WallTime{std::chrono::milliseconds{ms / 10 * 10}};
  const std::time_t tt = static_cast<std::time_t>(ms / 1000);
  std::tm utc{};
  gmtime_r(&tt, &utc);
  const auto hhmmss = fmt::format("{:02d}{:02d}{:02d}.{:02d}", utc.tm_hour, utc.tm_min, utc.tm_sec,
                                  static_cast<int>(ms % 1000) / 10);
  const auto ddmmyy =
      fmt::format("{:02d}{:02d}{:02d}", utc.tm_mday, utc.tm_mon + 1, utc.tm_year % 100);
  const auto la = nmea_angle(lat, 2);
  const auto lo = nmea_angle(lon, 3);
  const double knots = speed_mps / 0.514444;
  e.datagram =
      nmea_sentence(fmt::format("GPRMC,{},A,{},N,{},E,{:.3f},{:.1f},{},,,A", hhmmss, la, lo, knots,
                                course_deg, ddmmyy)) +
      nmea_sentence(fmt::format("GPGGA,{},{},N,{},E,1,09,0.9,500.0,M,47.0,M,,", hhmmss, la, lo)) +
      nmea_sentence("GPGSA,A,3,01,02,03,04,05,06,07,08,09,,,,1.5,0.9,1.2");
  return e;
}

}  // namespace tb::its::facilities::testing
