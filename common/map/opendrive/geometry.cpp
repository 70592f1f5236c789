#include "common/map/opendrive/geometry.hpp"

#include <algorithm>
#include <cmath>
#include <complex>

namespace tb::map::odr {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

void fresnel(double x, double& c, double& s) {
  const double ax = std::fabs(x);
  if (ax < 1.5) {
    // Power series: C = sum (-1)^n (pi/2)^(2n) x^(4n+1) / ((2n)! (4n+1)), S likewise with the
    // odd powers of pi/2. Terms stay below ~10 here, so doubles keep ~15 digits.
    const double h = kPi / 2.0 * ax * ax;  // (pi/2) x^2
    double term = ax;                      // (pi/2)^k x^(2k+1) / k!, k = 0
    double sum_c = 0.0;
    double sum_s = 0.0;
    for (int k = 0; k < 60; ++k) {
      const double contribution = term / (2.0 * k + 1.0);
      if (k % 4 == 0)
        sum_c += contribution;
      if (k % 4 == 1)
        sum_s += contribution;
      if (k % 4 == 2)
        sum_c -= contribution;
      if (k % 4 == 3)
        sum_s -= contribution;
      term *= h / (k + 1.0);
      if (term < 1e-18 * (std::fabs(sum_c) + std::fabs(sum_s)))
        break;
    }
    c = sum_c;
    s = sum_s;
  } else {
    // C + iS = (1+i)/2 (1 - e^(i pi x^2 / 2) w), w from the continued fraction of the
    // complementary error function at (1-i) sqrt(pi)/2 x, evaluated with Lentz's method.
    using Cx = std::complex<double>;
    const double pix2 = kPi * ax * ax;
    const double tiny = 1e-300;
    Cx b(1.0, -pix2);
    Cx cc = 1.0 / tiny;
    Cx d = 1.0 / b;
    Cx h = d;
    double n = -1.0;
    for (int k = 2; k < 200; ++k) {
      n += 2.0;
      const double a = -n * (n + 1.0);
      b += 4.0;
      d = 1.0 / (a * d + b);
      cc = b + a / cc;
      const Cx del = cc * d;
      h *= del;
      if (std::fabs(del.real() - 1.0) + std::fabs(del.imag()) < 1e-16)
        break;
    }
    h *= Cx(ax, -ax);
    const Cx cs = Cx(0.5, 0.5) * (1.0 - Cx(std::cos(0.5 * pix2), std::sin(0.5 * pix2)) * h);
    c = cs.real();
    s = cs.imag();
  }
  if (x < 0) {
    c = -c;
    s = -s;
  }
}

RefPoint Geometry::place(double u, double v, double local_hdg) const {
  const double ch = std::cos(start_.hdg);
  const double sh = std::sin(start_.hdg);
  return {start_.x + u * ch - v * sh, start_.y + u * sh + v * ch, start_.hdg + local_hdg};
}

RefPoint Line::at(double ds) const {
  return place(ds, 0.0, 0.0);
}

Arc::Arc(double s0, RefPoint start, double length, double curvature)
    : Geometry(s0, start, length), k_(curvature) {}

RefPoint Arc::at(double ds) const {
  const double a = k_ * ds;
  if (std::fabs(a) < 1e-9) {
    // sin(a)/k and (1-cos a)/k lose digits for tiny a; their Taylor forms do not.
    return place(ds * (1.0 - a * a / 6.0), ds * a / 2.0, a);
  }
  return place(std::sin(a) / k_, (1.0 - std::cos(a)) / k_, a);
}

Spiral::Spiral(double s0, RefPoint start, double length, double k_start, double k_end)
    : Geometry(s0, start, length), k0_(k_start), c_((k_end - k_start) / length) {
  // Mirror a clothoid whose curvature falls so that the closed form sees a rising one.
  sigma_ = c_ < 0 ? -1.0 : 1.0;
  const double k0 = sigma_ * k0_;
  const double c = sigma_ * c_;
  scale_ = std::sqrt(kPi / c);
  t0_ = k0 / std::sqrt(c * kPi);
  fresnel(t0_, c0_, s0f_);
  phi_ = -k0 * k0 / (2.0 * c);
}

RefPoint Spiral::at(double ds) const {
  const double k0 = sigma_ * k0_;
  const double c = sigma_ * c_;
  const double t1 = (ds + k0 / c) * std::sqrt(c / kPi);
  double c1 = 0.0;
  double s1 = 0.0;
  fresnel(t1, c1, s1);
  const double dc = c1 - c0_;
  const double dsn = s1 - s0f_;
  const double u = scale_ * (std::cos(phi_) * dc - std::sin(phi_) * dsn);
  const double v = scale_ * (std::sin(phi_) * dc + std::cos(phi_) * dsn);
  const double hdg = k0 * ds + c * ds * ds / 2.0;
  return place(u, sigma_ * v, sigma_ * hdg);
}

std::unique_ptr<Geometry> make_spiral(double s0, RefPoint start, double length, double k_start,
                                      double k_end) {
  // Below this change of curvature over the whole length the clothoid and the arc differ by
  // less than c L^3 / 6 < 1e-9 m on any road of a few km.
  if (std::fabs(k_end - k_start) < 1e-15 * std::max(1.0, length)) {
    if (k_start == 0.0)
      return std::make_unique<Line>(s0, start, length);
    return std::make_unique<Arc>(s0, start, length, k_start);
  }
  return std::make_unique<Spiral>(s0, start, length, k_start, k_end);
}

ParamPoly3::ParamPoly3(double s0, RefPoint start, double length, Coefficients c, bool normalized)
    : Geometry(s0, start, length),
      k_(c),
      normalized_(normalized),
      p_per_s_(normalized ? 1.0 / length : 1.0) {}

RefPoint ParamPoly3::at(double ds) const {
  const double p = ds * p_per_s_;
  const double u = k_.au + p * (k_.bu + p * (k_.cu + p * k_.du));
  const double v = k_.av + p * (k_.bv + p * (k_.cv + p * k_.dv));
  const double du = k_.bu + p * (2.0 * k_.cu + 3.0 * p * k_.du);
  const double dv = k_.bv + p * (2.0 * k_.cv + 3.0 * p * k_.dv);
  return place(u, v, std::atan2(dv, du));
}

double ParamPoly3::curvature(double ds) const {
  const double p = ds * p_per_s_;
  const double du = k_.bu + p * (2.0 * k_.cu + 3.0 * p * k_.du);
  const double dv = k_.bv + p * (2.0 * k_.cv + 3.0 * p * k_.dv);
  const double ddu = 2.0 * k_.cu + 6.0 * p * k_.du;
  const double ddv = 2.0 * k_.cv + 6.0 * p * k_.dv;
  const double n = std::pow(du * du + dv * dv, 1.5);
  return n > 0 ? (du * ddv - dv * ddu) / n : 0.0;
}

Poly3::Poly3(double s0, RefPoint start, double length, double a, double b, double c, double d)
    : Geometry(s0, start, length), a_(a), b_(b), c_(c), d_(d) {
  // u <= s, so u in [0, length] covers the geometry; Simpson on each step of the table.
  const int n = static_cast<int>(std::clamp(length / 0.25, 64.0, 8192.0));
  du_ = length / n;
  auto speed = [&](double u) {
    const double dv = b_ + u * (2.0 * c_ + 3.0 * d_ * u);
    return std::sqrt(1.0 + dv * dv);
  };
  arc_.resize(static_cast<std::size_t>(n) + 1);
  arc_[0] = 0.0;
  for (int i = 0; i < n; ++i) {
    const double u = i * du_;
    arc_[static_cast<std::size_t>(i) + 1] =
        arc_[static_cast<std::size_t>(i)] +
        du_ / 6.0 * (speed(u) + 4.0 * speed(u + du_ / 2.0) + speed(u + du_));
  }
}

double Poly3::u_of(double ds) const {
  const auto it = std::upper_bound(arc_.begin(), arc_.end(), ds);
  if (it == arc_.begin())
    return ds;  // before the start: extrapolate along u
  const auto i = static_cast<std::size_t>(it - arc_.begin()) - 1;
  if (i + 1 >= arc_.size())
    return (arc_.size() - 1) * du_ + (ds - arc_.back());
  const double f = (ds - arc_[i]) / (arc_[i + 1] - arc_[i]);
  return (static_cast<double>(i) + f) * du_;
}

RefPoint Poly3::at(double ds) const {
  const double u = u_of(ds);
  const double v = a_ + u * (b_ + u * (c_ + u * d_));
  const double dv = b_ + u * (2.0 * c_ + 3.0 * d_ * u);
  return place(u, v, std::atan(dv));
}

double Poly3::curvature(double ds) const {
  const double u = u_of(ds);
  const double dv = b_ + u * (2.0 * c_ + 3.0 * d_ * u);
  const double ddv = 2.0 * c_ + 6.0 * d_ * u;
  return ddv / std::pow(1.0 + dv * dv, 1.5);
}

}  // namespace tb::map::odr
