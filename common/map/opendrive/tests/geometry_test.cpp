// planView geometries against values worked out independently: Fresnel integrals and
// clothoids by composite Simpson quadrature of their defining integrals, arcs from their
// centre, polynomials from their formulas.

#include "common/map/opendrive/geometry.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

namespace tb::map::odr {
namespace {

constexpr double kPi = 3.14159265358979323846;

double simpson(const std::function<double(double)>& f, double a, double b, int n) {
  const double h = (b - a) / n;
  double sum = f(a) + f(b);
  for (int i = 1; i < n; ++i)
    sum += f(a + i * h) * (i % 2 == 1 ? 4.0 : 2.0);
  return sum * h / 3.0;
}

TEST(Fresnel, MatchesQuadratureOfItsDefinition) {
  for (double x : {-3.7, -1.2, 0.0, 0.3, 1.0, 1.49, 1.51, 2.0, 4.5, 7.25}) {
    double c = 0, s = 0;
    fresnel(x, c, s);
    const double qc = simpson([](double u) { return std::cos(kPi / 2 * u * u); }, 0, x, 20000);
    const double qs = simpson([](double u) { return std::sin(kPi / 2 * u * u); }, 0, x, 20000);
    EXPECT_NEAR(c, qc, 1e-11) << x;
    EXPECT_NEAR(s, qs, 1e-11) << x;
  }
}

TEST(Fresnel, TendsToOneHalf) {
  double c = 0, s = 0;
  fresnel(1e4, c, s);
  EXPECT_NEAR(c, 0.5, 1e-4);
  EXPECT_NEAR(s, 0.5, 1e-4);
}

/// Position along a curve of curvature k0 + c s from (x0, y0, hdg) by quadrature of the heading.
RefPoint integrate_clothoid(RefPoint start, double k0, double c, double ds) {
  auto hdg = [&](double u) { return start.hdg + k0 * u + c * u * u / 2; };
  return {start.x + simpson([&](double u) { return std::cos(hdg(u)); }, 0, ds, 4000),
          start.y + simpson([&](double u) { return std::sin(hdg(u)); }, 0, ds, 4000), hdg(ds)};
}

struct SpiralCase {
  double k_start, k_end, length;
};

class SpiralTest : public testing::TestWithParam<SpiralCase> {};

TEST_P(SpiralTest, MatchesQuadratureWithinAMillimetre) {
  const auto [k0, k1, len] = GetParam();
  const RefPoint start{12.5, -40.0, 0.7};
  auto g = make_spiral(100.0, start, len, k0, k1);
  EXPECT_EQ(g->s0(), 100.0);
  for (int i = 0; i <= 10; ++i) {
    const double ds = len * i / 10.0;
    const RefPoint want = integrate_clothoid(start, k0, (k1 - k0) / len, ds);
    const RefPoint got = g->at(ds);
    EXPECT_NEAR(got.x, want.x, 1e-3) << ds;
    EXPECT_NEAR(got.y, want.y, 1e-3) << ds;
    EXPECT_NEAR(got.hdg, want.hdg, 1e-9) << ds;
    EXPECT_NEAR(std::hypot(got.x - want.x, got.y - want.y), 0.0, 1e-6) << ds;
    EXPECT_NEAR(g->curvature(ds), k0 + (k1 - k0) * ds / len, 1e-12);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Clothoids, SpiralTest,
    testing::Values(SpiralCase{0.0, 0.01, 100.0},        // from a straight
                    SpiralCase{-1e-9, -0.125, 8.3776},   // the 4-way junction's turn-in
                    SpiralCase{-0.125, -1e-9, 8.3776},   // and its turn-out
                    SpiralCase{0.001, 0.02, 150.0},      // non-zero start curvature
                    SpiralCase{-0.01, -1e-5, 300.0},     // falling curvature, long
                    SpiralCase{0.05, -0.05, 60.0},       // S-bend through zero
                    SpiralCase{0.1, 0.1000001, 50.0}));  // nearly an arc: far-out Fresnel

TEST(SpiralTest, ConstantCurvatureBecomesArcOrLine) {
  const RefPoint start{1, 2, 0.3};
  auto arc = make_spiral(0, start, 10, 0.05, 0.05);
  EXPECT_NE(dynamic_cast<Arc*>(arc.get()), nullptr);
  auto line = make_spiral(0, start, 10, 0.0, 0.0);
  EXPECT_NE(dynamic_cast<Line*>(line.get()), nullptr);
}

TEST(LineTest, RunsAlongTheHeading) {
  Line l(0, {3, 4, kPi / 6}, 20);
  const RefPoint p = l.at(10);
  EXPECT_NEAR(p.x, 3 + 10 * std::sqrt(3.0) / 2, 1e-12);
  EXPECT_NEAR(p.y, 4 + 5, 1e-12);
  EXPECT_NEAR(p.hdg, kPi / 6, 1e-15);
}

TEST(ArcTest, StaysOnItsCircle) {
  for (double k : {0.02, -0.05, 1e-12}) {
    const RefPoint start{10, -5, 1.1};
    Arc a(0, start, 80, k);
    for (double ds : {0.0, 13.0, 40.0, 80.0}) {
      const RefPoint p = a.at(ds);
      EXPECT_NEAR(p.hdg, start.hdg + k * ds, 1e-12);
      if (std::fabs(k) > 1e-6) {
        const double r = 1 / k;  // centre to the left for k > 0
        const double cx = start.x - r * std::sin(start.hdg);
        const double cy = start.y + r * std::cos(start.hdg);
        EXPECT_NEAR(std::hypot(p.x - cx, p.y - cy), std::fabs(r), 1e-9) << k << " " << ds;
        EXPECT_NEAR(p.x, cx + r * std::sin(p.hdg), 1e-9);
      } else {
        EXPECT_NEAR(p.x, start.x + ds * std::cos(start.hdg), 1e-6);
      }
    }
  }
}

TEST(ParamPoly3Test, BothParameterRangesEndWhereTheCubicEnds) {
  ParamPoly3::Coefficients c;
  c.bu = 20;
  c.cu = -1;
  c.cv = 3;
  c.dv = -1;
  ParamPoly3 normalized(0, {0, 0, 0}, 20.3, c, true);
  const RefPoint e = normalized.at(20.3);  // p = 1
  EXPECT_NEAR(e.x, 19.0, 1e-12);
  EXPECT_NEAR(e.y, 2.0, 1e-12);
  EXPECT_NEAR(e.hdg, std::atan2(3.0, 18.0), 1e-12);

  ParamPoly3::Coefficients a;  // arcLength: p = s
  a.bu = 1;
  a.cv = 0.01;
  ParamPoly3 arc(5, {1, 1, kPi / 2}, 10, a, false);
  const RefPoint m = arc.at(10);  // u = 10, v = 1, rotated by 90 degrees
  EXPECT_NEAR(m.x, 1 - 1.0, 1e-12);
  EXPECT_NEAR(m.y, 1 + 10.0, 1e-12);
  EXPECT_NEAR(arc.curvature(0), 0.02, 1e-12);
}

TEST(Poly3Test, MapsArcLengthToU) {
  const double b = 0.5;  // a straight line v = b u at slope b: s = u sqrt(1 + b^2)
  Poly3 p(0, {0, 0, 0}, 30, 0, b, 0, 0);
  const RefPoint q = p.at(10 * std::sqrt(1 + b * b));
  EXPECT_NEAR(q.x, 10, 1e-6);
  EXPECT_NEAR(q.y, 5, 1e-6);
  EXPECT_NEAR(q.hdg, std::atan(b), 1e-12);
  // A cubic: arc length from the start to the returned point equals ds.
  Poly3 cubic(0, {0, 0, 0}, 40, 0, 0, 0.01, -0.0002);
  const double ds = 25;
  const RefPoint r = cubic.at(ds);
  const double arc = simpson(
      [](double u) {
        const double dv = 0.02 * u - 0.0006 * u * u;
        return std::sqrt(1 + dv * dv);
      },
      0, r.x, 2000);
  EXPECT_NEAR(arc, ds, 1e-3);
  EXPECT_NEAR(r.y, 0.01 * r.x * r.x - 0.0002 * r.x * r.x * r.x, 1e-9);
}

}  // namespace
}  // namespace tb::map::odr
