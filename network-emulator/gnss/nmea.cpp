#include "network-emulator/gnss/nmea.hpp"

#include <cmath>
#include <ctime>

#include <fmt/format.h>

namespace tb::emu::gnss {

std::uint8_t nmea_checksum(std::string_view body) {
  std::uint8_t c = 0;
  for (char ch : body)
    c ^= static_cast<std::uint8_t>(ch);
  return c;
}

namespace {

using Buffer = fmt::memory_buffer;

/// Appends "*hh\r\n" after the sentence that starts at @p begin.
void finish(std::string& out, std::size_t begin) {
  const std::uint8_t c = nmea_checksum(std::string_view(out).substr(begin + 1));
  static constexpr char kHex[] = "0123456789ABCDEF";
  out += '*';
  out += kHex[c >> 4];
  out += kHex[c & 0xF];
  out += "\r\n";
}

struct UtcParts {
  int hour, minute, second, millisecond, day, month, year2;
};

UtcParts split(std::chrono::system_clock::time_point t) {
  using namespace std::chrono;
  const auto ms = floor<milliseconds>(t);
  const auto day = floor<days>(ms);
  const year_month_day ymd{day};
  const hh_mm_ss<milliseconds> hms{ms - day};
  return {static_cast<int>(hms.hours().count()),
          static_cast<int>(hms.minutes().count()),
          static_cast<int>(hms.seconds().count()),
          static_cast<int>(hms.subseconds().count()),
          static_cast<int>(static_cast<unsigned>(ymd.day())),
          static_cast<int>(static_cast<unsigned>(ymd.month())),
          static_cast<int>(ymd.year()) % 100};
}

/// Degrees → "ddmm.mmmmmm" (or "dddmm.mmmmmm") and hemisphere. Rounds in whole millionths
/// of a minute (1.9 mm) so that 59.9999996' never prints as 60'.
void append_angle(std::string& out, double deg, int degree_digits, char pos, char neg) {
  const auto micro_min = static_cast<std::int64_t>(std::llround(std::abs(deg) * 60e6));
  const std::int64_t whole_deg = micro_min / 60'000'000;
  const std::int64_t rest = micro_min % 60'000'000;
  fmt::format_to(std::back_inserter(out), "{:0{}d}{:02d}.{:06d},{}", whole_deg, degree_digits,
                 rest / 1'000'000, rest % 1'000'000, deg < 0 ? neg : pos);
}

}  // namespace

void append_epoch(const Fix& fix, std::string& out) {
  const UtcParts t = split(fix.time);
  char time_field[16];
  fmt::format_to_n(time_field, sizeof time_field, "{:02d}{:02d}{:02d}.{:03d}", t.hour, t.minute,
                   t.second, t.millisecond);
  const std::string_view hms(time_field, 10);
  auto o = std::back_inserter(out);

  std::size_t used = 0;
  for (const SatelliteView& s : fix.sky)
    used += s.used ? 1 : 0;
  const double knots = fix.speed_mps * kKnotsPerMps;
  const double course = fix.course_deg >= 359.995 ? 0.0 : fix.course_deg;

  // RMC: time, status, position, speed (knots), course, date, magnetic variation, mode.
  std::size_t b = out.size();
  if (fix.valid) {
    fmt::format_to(o, "$GPRMC,{},A,", hms);
    append_angle(out, fix.position.latitude_deg, 2, 'N', 'S');
    out += ',';
    append_angle(out, fix.position.longitude_deg, 3, 'E', 'W');
    fmt::format_to(o, ",{:.3f},{:.2f},{:02d}{:02d}{:02d},,,A", knots, course, t.day, t.month,
                   t.year2);
  } else {
    fmt::format_to(o, "$GPRMC,{},V,,,,,,,{:02d}{:02d}{:02d},,,N", hms, t.day, t.month, t.year2);
  }
  finish(out, b);

  // VTG: true course, magnetic course (none), speed in knots and km/h, mode.
  b = out.size();
  if (fix.valid)
    fmt::format_to(o, "$GPVTG,{:.2f},T,,M,{:.3f},N,{:.3f},K,A", course, knots, fix.speed_mps * 3.6);
  else
    fmt::format_to(o, "$GPVTG,,T,,M,,N,,K,N");
  finish(out, b);

  // GGA: quality 1 (autonomous GNSS fix), satellites used, HDOP, altitude, geoid separation.
  b = out.size();
  if (fix.valid) {
    fmt::format_to(o, "$GPGGA,{},", hms);
    append_angle(out, fix.position.latitude_deg, 2, 'N', 'S');
    out += ',';
    append_angle(out, fix.position.longitude_deg, 3, 'E', 'W');
    fmt::format_to(o, ",1,{:02d},{:.2f},{:.3f},M,0.0,M,,", used, fix.hdop, fix.position.altitude_m);
  } else {
    fmt::format_to(o, "$GPGGA,{},,,,,0,00,,,M,,M,,", hms);
  }
  finish(out, b);

  // GSA: automatic 2D/3D, fix mode, up to 12 PRNs used, PDOP, HDOP, VDOP.
  b = out.size();
  const int mode = !fix.valid ? 1 : used >= 4 ? 3 : 2;
  fmt::format_to(o, "$GPGSA,A,{}", mode);
  std::size_t listed = 0;
  if (fix.valid)
    for (const SatelliteView& s : fix.sky)
      if (s.used && listed < kMaxGsaSatellites) {
        fmt::format_to(o, ",{:02d}", s.prn);
        ++listed;
      }
  for (; listed < kMaxGsaSatellites; ++listed)
    out += ',';
  if (fix.valid)
    fmt::format_to(o, ",{:.2f},{:.2f},{:.2f}", fix.pdop, fix.hdop, fix.vdop);
  else
    out += ",,,";
  finish(out, b);

  // GSV: satellites in view, four per sentence (none while the fix is lost).
  const std::size_t in_view = fix.valid ? fix.sky.size() : 0;
  const std::size_t sentences = in_view == 0 ? 1 : (in_view + 3) / 4;
  for (std::size_t n = 0; n < sentences; ++n) {
    b = out.size();
    fmt::format_to(o, "$GPGSV,{},{},{:02d}", sentences, n + 1, in_view);
    for (std::size_t i = n * 4; i < std::min(in_view, n * 4 + 4); ++i) {
      const SatelliteView& s = fix.sky[i];
      fmt::format_to(o, ",{:02d},{:02d},{:03d},{:02d}", s.prn,
                     static_cast<int>(std::lround(s.elevation_deg)),
                     static_cast<int>(std::lround(s.azimuth_deg)) % 360, s.snr_db);
    }
    finish(out, b);
  }

  // GST: range residual RMS, error ellipse (axes aligned with north/east), 1-sigma errors.
  b = out.size();
  if (fix.valid) {
    const double major = std::max(fix.sigma_lat_m, fix.sigma_lon_m);
    const double minor = std::min(fix.sigma_lat_m, fix.sigma_lon_m);
    const double orientation = fix.sigma_lat_m >= fix.sigma_lon_m ? 0.0 : 90.0;
    fmt::format_to(o, "$GPGST,{},{:.2f},{:.2f},{:.2f},{:.1f},{:.2f},{:.2f},{:.2f}", hms,
                   fix.range_rms_m, major, minor, orientation, fix.sigma_lat_m, fix.sigma_lon_m,
                   fix.sigma_alt_m);
  } else {
    fmt::format_to(o, "$GPGST,{},,,,,,,", hms);
  }
  finish(out, b);
}

}  // namespace tb::emu::gnss
