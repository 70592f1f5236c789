#include <cmath>

#include <gtest/gtest.h>

#include "network-emulator/gnss/nmea.hpp"
#include "network-emulator/gnss/sky.hpp"
#include "network-emulator/gnss/tests/nmea_parse.hpp"

namespace tb::emu::gnss {
namespace {

using testing::nmea_degrees;
using testing::parse_datagram;

Fix sample_fix() {
  Fix f;
  // 2025-01-01T12:34:56.780Z
  f.time = std::chrono::system_clock::time_point{std::chrono::milliseconds{1735734896780LL}};
  f.position = {48.1234567, -11.5000001, 512.25};
  f.speed_mps = 13.89;
  f.course_deg = 271.5;
  f.hdop = 0.9;
  f.vdop = 1.2;
  f.pdop = 1.5;
  f.sky = make_sky(9, 0.9, 7);
  f.sigma_lat_m = 1.25;
  f.sigma_lon_m = 1.25;
  f.sigma_alt_m = 2.5;
  f.range_rms_m = 1.25;
  return f;
}

TEST(Nmea, EpochHasTheSentencesInOrderWithOneTimeAndGoodChecksums) {
  std::string out;
  append_epoch(sample_fix(), out);
  const auto s = parse_datagram(out);
  std::vector<std::string> types;
  for (const auto& x : s) {
    types.push_back(x.type);
    EXPECT_TRUE(x.checksum_ok) << x.type;
    EXPECT_LE(x.length, 82u) << x.type << " longer than NMEA's 82 characters";
  }
  EXPECT_EQ(types, (std::vector<std::string>{"GPRMC", "GPVTG", "GPGGA", "GPGSA", "GPGSV", "GPGSV",
                                             "GPGSV", "GPGST"}));
  EXPECT_EQ(s[0].fields[0], "123456.780");  // RMC
  EXPECT_EQ(s[2].fields[0], "123456.780");  // GGA
  EXPECT_EQ(s[7].fields[0], "123456.780");  // GST
}

TEST(Nmea, FieldsParseBackToTheFix) {
  const Fix f = sample_fix();
  std::string out;
  append_epoch(f, out);
  const auto s = parse_datagram(out);
  const auto& rmc = s[0].fields;
  EXPECT_EQ(rmc[1], "A");
  EXPECT_NEAR(nmea_degrees(rmc[2], rmc[3], 2), 48.1234567, 1e-8);
  EXPECT_NEAR(nmea_degrees(rmc[4], rmc[5], 3), -11.5000001, 1e-8);
  EXPECT_EQ(rmc[5], "W");
  EXPECT_NEAR(std::stod(rmc[6]) / kKnotsPerMps, 13.89, 0.001);
  EXPECT_DOUBLE_EQ(std::stod(rmc[7]), 271.5);
  EXPECT_EQ(rmc[8], "010125");
  EXPECT_EQ(rmc[11], "A");

  const auto& vtg = s[1].fields;
  EXPECT_DOUBLE_EQ(std::stod(vtg[0]), 271.5);
  EXPECT_EQ(vtg[1], "T");
  EXPECT_NEAR(std::stod(vtg[6]), 13.89 * 3.6, 0.001);

  const auto& gga = s[2].fields;
  EXPECT_EQ(gga[5], "1");
  EXPECT_EQ(gga[6], "09");
  EXPECT_DOUBLE_EQ(std::stod(gga[7]), 0.9);
  EXPECT_DOUBLE_EQ(std::stod(gga[8]), 512.25);

  const auto& gsa = s[3].fields;
  EXPECT_EQ(gsa[0], "A");
  EXPECT_EQ(gsa[1], "3");
  int listed = 0;
  for (int i = 2; i < 14; ++i)
    listed += gsa[static_cast<std::size_t>(i)].empty() ? 0 : 1;
  EXPECT_EQ(listed, 9);
  EXPECT_DOUBLE_EQ(std::stod(gsa[14]), 1.5);
  EXPECT_DOUBLE_EQ(std::stod(gsa[15]), 0.9);
  EXPECT_DOUBLE_EQ(std::stod(gsa[16]), 1.2);

  // GSV: 3 sentences, 9 in view, every satellite with elevation and azimuth.
  int sats = 0;
  for (int i = 4; i < 7; ++i) {
    const auto& gsv = s[static_cast<std::size_t>(i)].fields;
    EXPECT_EQ(gsv[0], "3");
    EXPECT_EQ(gsv[1], std::to_string(i - 3));
    EXPECT_EQ(gsv[2], "09");
    for (std::size_t k = 3; k + 3 < gsv.size() + 1; k += 4) {
      EXPECT_FALSE(gsv[k + 1].empty());
      EXPECT_FALSE(gsv[k + 2].empty());
      ++sats;
    }
  }
  EXPECT_EQ(sats, 9);

  const auto& gst = s[7].fields;
  EXPECT_DOUBLE_EQ(std::stod(gst[5]), 1.25);
  EXPECT_DOUBLE_EQ(std::stod(gst[6]), 1.25);
  EXPECT_DOUBLE_EQ(std::stod(gst[7]), 2.5);
}

TEST(Nmea, MinutesNeverRoundUpToSixty) {
  Fix f = sample_fix();
  f.position.latitude_deg = 47.99999999999;  // 47° 59.99999999994'
  f.position.longitude_deg = 0.0;
  std::string out;
  append_epoch(f, out);
  const auto rmc = parse_datagram(out)[0].fields;
  EXPECT_EQ(rmc[2], "4800.000000");
  EXPECT_EQ(rmc[4], "00000.000000");
  EXPECT_EQ(rmc[5], "E");
}

TEST(Nmea, LostFixSaysSoInEverySentence) {
  Fix f = sample_fix();
  f.valid = false;
  std::string out;
  append_epoch(f, out);
  const auto s = parse_datagram(out);
  ASSERT_EQ(s.size(), 6u);  // one empty GSV
  for (const auto& x : s)
    EXPECT_TRUE(x.checksum_ok);
  EXPECT_EQ(s[0].fields[1], "V");
  EXPECT_TRUE(s[0].fields[2].empty());
  EXPECT_EQ(s[2].fields[5], "0");
  EXPECT_EQ(s[3].fields[1], "1");
  EXPECT_EQ(s[4].fields[2], "00");
}

TEST(Nmea, ChecksumOfAKnownSentence) {
  // The GGA example that circulates with NMEA 0183 descriptions ends in "*47".
  EXPECT_EQ(nmea_checksum("GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,"), 0x47);
}

TEST(Sky, DopOfASymmetricSkyMatchesTheClosedForm) {
  // Four satellites: one at the zenith, three at the horizon 120° apart. Worked out by hand:
  // GᵀG = diag(1.5, 1.5, 1, 4) with the off-diagonal up/clock term 1, so the
  // east/north variances are 1/1.5 and HDOP = sqrt(2/1.5) = 1.1547.
  std::vector<SatelliteView> sky{
      {1, 90, 0, 40, true}, {2, 0, 0, 40, true}, {3, 0, 120, 40, true}, {4, 0, 240, 40, true}};
  const auto d = compute_dop(sky);
  ASSERT_TRUE(d.has_value());
  EXPECT_NEAR(d->hdop, std::sqrt(2.0 / 1.5), 1e-9);
  EXPECT_NEAR(d->xdop, std::sqrt(1.0 / 1.5), 1e-9);
  // Vertical/clock block [[1,1],[1,4]] inverts to [[4,-1],[-1,1]]/3: VDOP = sqrt(4/3).
  EXPECT_NEAR(d->vdop, std::sqrt(4.0 / 3.0), 1e-9);
  sky.pop_back();
  EXPECT_FALSE(compute_dop(sky).has_value());
}

TEST(Sky, GeometryHasTheRequestedHdop) {
  for (int n : {4, 6, 9, 12}) {
    for (double target : {1.5, 2.0, 3.0}) {
      const auto sky = make_sky(n, target, 99);
      ASSERT_EQ(sky.size(), static_cast<std::size_t>(n));
      const auto d = compute_dop(sky);
      ASSERT_TRUE(d.has_value());
      EXPECT_NEAR(d->hdop, target, 0.01 * target) << n << " satellites";
      for (const auto& s : sky) {
        EXPECT_GE(s.elevation_deg, 0);
        EXPECT_LE(s.elevation_deg, 90);
        EXPECT_GE(s.prn, 1);
        EXPECT_LE(s.prn, 32);
      }
    }
  }
  EXPECT_NEAR(compute_dop(make_sky(9, 0.9, 1))->hdop, 0.9, 0.01);
}

TEST(Sky, SameSeedSameSky) {
  const auto a = make_sky(9, 1.0, 5), b = make_sky(9, 1.0, 5), c = make_sky(9, 1.0, 6);
  EXPECT_EQ(a[3].prn, b[3].prn);
  EXPECT_DOUBLE_EQ(a[3].azimuth_deg, b[3].azimuth_deg);
  EXPECT_FALSE(a[3].prn == c[3].prn && a[3].azimuth_deg == c[3].azimuth_deg);
}

}  // namespace
}  // namespace tb::emu::gnss
