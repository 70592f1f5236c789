#include "network-emulator/gnss/sky.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <random>

namespace tb::emu::gnss {

namespace {

using Mat4 = std::array<std::array<double, 4>, 4>;

/// Gauss-Jordan with partial pivoting; empty if singular.
std::optional<Mat4> invert(Mat4 a) {
  Mat4 inv{};
  for (int i = 0; i < 4; ++i)
    inv[i][i] = 1.0;
  for (int c = 0; c < 4; ++c) {
    int p = c;
    for (int r = c + 1; r < 4; ++r)
      if (std::abs(a[r][c]) > std::abs(a[p][c]))
        p = r;
    if (std::abs(a[p][c]) < 1e-12)
      return std::nullopt;
    std::swap(a[p], a[c]);
    std::swap(inv[p], inv[c]);
    const double d = a[c][c];
    for (int k = 0; k < 4; ++k) {
      a[c][k] /= d;
      inv[c][k] /= d;
    }
    for (int r = 0; r < 4; ++r) {
      if (r == c)
        continue;
      const double f = a[r][c];
      for (int k = 0; k < 4; ++k) {
        a[r][k] -= f * a[c][k];
        inv[r][k] -= f * inv[c][k];
      }
    }
  }
  return inv;
}

constexpr double kDeg = std::numbers::pi / 180.0;

}  // namespace

std::optional<Dop> compute_dop(std::span<const SatelliteView> sky) {
  Mat4 n{};  // GᵀG, G rows = unit line of sight (E, N, U) and 1 for the clock
  int used = 0;
  for (const SatelliteView& s : sky) {
    if (!s.used)
      continue;
    const double el = s.elevation_deg * kDeg, az = s.azimuth_deg * kDeg;
    const std::array<double, 4> g{std::cos(el) * std::sin(az), std::cos(el) * std::cos(az),
                                  std::sin(el), 1.0};
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j)
        n[i][j] += g[i] * g[j];
    ++used;
  }
  if (used < 4)
    return std::nullopt;
  const auto q = invert(n);
  if (!q)
    return std::nullopt;
  const Mat4& m = *q;
  if (m[0][0] <= 0 || m[1][1] <= 0 || m[2][2] <= 0 || m[3][3] <= 0)
    return std::nullopt;
  Dop d;
  d.xdop = std::sqrt(m[0][0]);
  d.ydop = std::sqrt(m[1][1]);
  d.hdop = std::sqrt(m[0][0] + m[1][1]);
  d.vdop = std::sqrt(m[2][2]);
  d.pdop = std::sqrt(m[0][0] + m[1][1] + m[2][2]);
  d.tdop = std::sqrt(m[3][3]);
  d.gdop = std::sqrt(m[0][0] + m[1][1] + m[2][2] + m[3][3]);
  return d;
}

namespace {

/// One satellite near the zenith and the others on a ring around the sky, alternating
/// between two elevations; @p t in [0, 1] lifts the ring from the horizon towards the zenith,
/// which worsens the horizontal geometry monotonically.
std::vector<SatelliteView> layout(int count, double t, std::span<const double> azimuth_jitter,
                                  std::span<const int> prns, double base_azimuth) {
  std::vector<SatelliteView> sky;
  const int used = std::min(count, static_cast<int>(kMaxGsaSatellites));
  const double low = 5.0 + 70.0 * t;
  const double high = std::min(low + 25.0, 85.0);
  for (int i = 0; i < count; ++i) {
    SatelliteView s;
    s.prn = prns[static_cast<std::size_t>(i)];
    if (i == 0) {
      s.elevation_deg = 88.0;
      s.azimuth_deg = base_azimuth;
    } else {
      const double step = 360.0 / (count - 1);
      s.elevation_deg = (i % 2) ? low : high;
      s.azimuth_deg = std::fmod(
          base_azimuth + step * i + azimuth_jitter[static_cast<std::size_t>(i)] * step * 0.2,
          360.0);
    }
    // Stronger signals from higher satellites, as a clear sky would give.
    s.snr_db = 30 + static_cast<int>(std::lround(s.elevation_deg / 90.0 * 20.0));
    s.used = i < used;
    sky.push_back(s);
  }
  return sky;
}

}  // namespace

std::vector<SatelliteView> make_sky(int count, double target_hdop, std::uint64_t seed) {
  count = std::clamp(count, 4, 32);
  std::mt19937_64 rng(seed);
  std::vector<int> prns(32);
  for (int i = 0; i < 32; ++i)
    prns[static_cast<std::size_t>(i)] = i + 1;
  std::shuffle(prns.begin(), prns.end(), rng);
  prns.resize(static_cast<std::size_t>(count));
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<double> jitter(static_cast<std::size_t>(count));
  for (double& j : jitter)
    j = unit(rng);
  const double base = std::uniform_real_distribution<double>(0.0, 360.0)(rng);

  auto hdop_at = [&](double t) {
    const auto d = compute_dop(layout(count, t, jitter, prns, base));
    return d ? d->hdop : 1e9;
  };
  double lo = 0.0, hi = 1.0;
  if (hdop_at(lo) >= target_hdop)
    return layout(count, lo, jitter, prns, base);
  if (hdop_at(hi) <= target_hdop)
    return layout(count, hi, jitter, prns, base);
  for (int i = 0; i < 40; ++i) {
    const double mid = 0.5 * (lo + hi);
    (hdop_at(mid) < target_hdop ? lo : hi) = mid;
  }
  return layout(count, 0.5 * (lo + hi), jitter, prns, base);
}

}  // namespace tb::emu::gnss
