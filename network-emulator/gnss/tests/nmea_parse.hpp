#pragma once
// A deliberately independent NMEA reader for the tests: splits a datagram into sentences,
// checks framing and checksums, and converts the fields the tests look at.

#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

namespace tb::emu::gnss::testing {

struct Sentence {
  std::string type;                 // "GPRMC", ...
  std::vector<std::string> fields;  // after the type
  bool checksum_ok = false;
  std::size_t length = 0;  // with "\r\n"
};

inline std::vector<Sentence> parse_datagram(std::string_view d) {
  std::vector<Sentence> out;
  while (!d.empty()) {
    const auto end = d.find("\r\n");
    const std::string_view line = d.substr(0, end);
    Sentence s;
    s.length = line.size() + 2;
    const auto star = line.rfind('*');
    if (line.empty() || line[0] != '$' || star == std::string_view::npos || star + 3 != line.size())
      return {};
    unsigned x = 0;
    for (char c : line.substr(1, star - 1))
      x ^= static_cast<unsigned char>(c);
    s.checksum_ok = std::strtoul(std::string(line.substr(star + 1)).c_str(), nullptr, 16) == x;
    std::string body(line.substr(1, star - 1));
    std::size_t p = 0;
    bool first = true;
    while (true) {
      const auto comma = body.find(',', p);
      const std::string f =
          body.substr(p, comma == std::string::npos ? std::string::npos : comma - p);
      if (first)
        s.type = f;
      else
        s.fields.push_back(f);
      first = false;
      if (comma == std::string::npos)
        break;
      p = comma + 1;
    }
    out.push_back(s);
    if (end == std::string_view::npos)
      break;
    d = d.substr(end + 2);
  }
  return out;
}

/// "ddmm.mmmm" + hemisphere → signed degrees.
inline double nmea_degrees(const std::string& value, const std::string& hemisphere,
                           int deg_digits) {
  const double deg = std::stod(value.substr(0, static_cast<std::size_t>(deg_digits)));
  const double min = std::stod(value.substr(static_cast<std::size_t>(deg_digits)));
  const double v = deg + min / 60.0;
  return (hemisphere == "S" || hemisphere == "W") ? -v : v;
}

}  // namespace tb::emu::gnss::testing
