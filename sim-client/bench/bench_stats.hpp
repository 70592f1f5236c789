#pragma once
// For the bench programs: percentiles of a sample and the machine's load average.

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

namespace tb::client::bench {

/// The @p p quantile (0..1) of @p v, linear between neighbours; NaN when empty.
inline double percentile(std::vector<double> v, double p) {
  if (v.empty())
    return NAN;
  std::sort(v.begin(), v.end());
  const double idx = p * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(idx));
  const auto hi = std::min(v.size() - 1, lo + 1);
  return v[lo] + (v[hi] - v[lo]) * (idx - static_cast<double>(lo));
}

/// The 1, 5 and 15 minute load averages, as uptime prints them.
inline std::string loadavg() {
  std::ifstream f("/proc/loadavg");
  std::string a, b, c;
  f >> a >> b >> c;
  return a + " " + b + " " + c;
}

}  // namespace tb::client::bench
