#pragma once
/// @file planView geometries of ASAM OpenDRIVE (1.7, clause 7.4-7.7): one class per element
/// behind one interface, each evaluated at a distance ds from its own start.

#include <memory>
#include <vector>

namespace tb::map::odr {

/// A point on a reference line: position in the inertial frame and heading (rad, ccw from x).
struct RefPoint {
  double x = 0.0;
  double y = 0.0;
  double hdg = 0.0;
};

/// Fresnel integrals C(x) = int_0^x cos(pi/2 u^2) du and S(x) = int_0^x sin(pi/2 u^2) du, to
/// about 1e-15 absolute (power series near 0, a continued fraction further out).
void fresnel(double x, double& c, double& s);

/// The common part of every planView <geometry>: start s, start pose, length.
class Geometry {
 public:
  Geometry(double s0, RefPoint start, double length) : s0_(s0), start_(start), length_(length) {}
  virtual ~Geometry() = default;

  double s0() const { return s0_; }
  double length() const { return length_; }
  const RefPoint& start() const { return start_; }
  /// The pose @p ds metres along this geometry (0 <= ds <= length; extrapolated outside).
  virtual RefPoint at(double ds) const = 0;
  /// Curvature (1/m, positive to the left) at ds; used to pick mesh and index steps.
  virtual double curvature(double ds) const = 0;

 protected:
  /// Local (u, v) in the geometry's start frame to the inertial frame.
  RefPoint place(double u, double v, double local_hdg) const;

 private:
  double s0_;
  RefPoint start_;
  double length_;
};

class Line final : public Geometry {
 public:
  using Geometry::Geometry;
  RefPoint at(double ds) const override;
  double curvature(double) const override { return 0.0; }
};

class Arc final : public Geometry {
 public:
  Arc(double s0, RefPoint start, double length, double curvature);
  RefPoint at(double ds) const override;
  double curvature(double) const override { return k_; }

 private:
  double k_;
};

/// Clothoid: curvature linear in s from curvStart to curvEnd (either may be non-zero),
/// evaluated in closed form with Fresnel integrals. A spiral whose curvature does not change
/// measurably is made an Arc or Line by make_spiral() instead.
class Spiral final : public Geometry {
 public:
  Spiral(double s0, RefPoint start, double length, double k_start, double k_end);
  RefPoint at(double ds) const override;
  double curvature(double ds) const override { return k0_ + c_ * ds; }
  double curvature_start() const { return k0_; }
  double curvature_end() const { return k0_ + c_ * length(); }

 private:
  double k0_;
  double c_;  ///< curvature change per metre
  // Closed form: with sigma = +-1 the sign of c, the clothoid is the Fresnel spiral scaled by
  // sqrt(pi/|c|), rotated by phi_, starting at parameter t0_.
  double sigma_ = 1.0;
  double scale_ = 0.0;
  double t0_ = 0.0;
  double c0_ = 0.0;
  double s0f_ = 0.0;
  double phi_ = 0.0;
};

std::unique_ptr<Geometry> make_spiral(double s0, RefPoint start, double length, double k_start,
                                      double k_end);

/// <paramPoly3>: (u(p), v(p)) cubics in the start frame. p runs linearly with s over the
/// geometry, from 0 to 1 ("normalized") or to the length ("arcLength"), so that both ends sit
/// exactly where the file puts them.
class ParamPoly3 final : public Geometry {
 public:
  struct Coefficients {
    double au = 0, bu = 0, cu = 0, du = 0;
    double av = 0, bv = 0, cv = 0, dv = 0;
  };
  ParamPoly3(double s0, RefPoint start, double length, Coefficients c, bool normalized);
  RefPoint at(double ds) const override;
  double curvature(double ds) const override;
  const Coefficients& coefficients() const { return k_; }
  bool normalized() const { return normalized_; }

 private:
  Coefficients k_;
  bool normalized_;
  double p_per_s_;
};

/// <poly3> (deprecated in 1.6, still common): v = a + b u + c u^2 + d u^3 in the start frame.
/// s -> u goes through an arc-length table, since u is not the arc length.
class Poly3 final : public Geometry {
 public:
  Poly3(double s0, RefPoint start, double length, double a, double b, double c, double d);
  RefPoint at(double ds) const override;
  double curvature(double ds) const override;
  double a() const { return a_; }
  double b() const { return b_; }
  double c() const { return c_; }
  double d() const { return d_; }

 private:
  double u_of(double ds) const;
  double a_, b_, c_, d_;
  double du_;                ///< u step of the table
  std::vector<double> arc_;  ///< arc length at u = i * du_
};

}  // namespace tb::map::odr
