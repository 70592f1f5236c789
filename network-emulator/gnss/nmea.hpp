#pragma once
/// @file NMEA 0183 sentences of one receiver epoch, as gpsd needs them for a full fix.
///
/// An epoch is RMC, VTG, GGA, GSA, GSV (one to three sentences) and GST, in that order, all
/// with the same UTC time of the fix (gpsd ends a reporting cycle when the time changes), GPS
/// talker ID "GP", each ended by "*hh\r\n" with the XOR checksum (NMEA 0183 v4.10, 5.2.3).

#include <chrono>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "common/geodesy/wgs84.hpp"

namespace tb::emu::gnss {

struct SatelliteView {
  int prn = 1;                 ///< 1..32 (GPS)
  double elevation_deg = 0.0;  ///< 0..90
  double azimuth_deg = 0.0;    ///< 0..359, clockwise from true north
  int snr_db = 40;             ///< C/N0, dB-Hz
  bool used = true;            ///< used in the fix (listed in GSA)
};

/// Everything the sentences of one epoch say.
struct Fix {
  std::chrono::system_clock::time_point time;  ///< UTC time of the fix
  bool valid = true;                           ///< false: no fix (status V, quality 0)
  geodesy::Geodetic position;                  ///< altitude reported as MSL, see README
  double speed_mps = 0.0;                      ///< speed over ground
  double course_deg = 0.0;                     ///< true course, clockwise from north, [0, 360)
  double pdop = 1.5, hdop = 0.9, vdop = 1.2;
  std::vector<SatelliteView> sky;  ///< satellites in view
  /// GST: 1-sigma errors in metres, and the RMS of the range residuals.
  double sigma_lat_m = 0.0, sigma_lon_m = 0.0, sigma_alt_m = 0.0, range_rms_m = 0.0;
};

inline constexpr double kKnotsPerMps = 3600.0 / 1852.0;
/// GSA lists at most 12 satellites (NMEA 0183).
inline constexpr std::size_t kMaxGsaSatellites = 12;

/// Appends the epoch's sentences to @p out (which is not cleared).
void append_epoch(const Fix& fix, std::string& out);
/// XOR of the characters between '$' and '*' (both excluded).
std::uint8_t nmea_checksum(std::string_view body);

}  // namespace tb::emu::gnss
