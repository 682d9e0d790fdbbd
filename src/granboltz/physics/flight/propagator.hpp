#pragma once
// The exact propagator of the linear free flight dv = -A v dt + sqrt(2 beta) dW with
// A = gamma I + a e_x e_y^T: white noise (A = 0), drag (A = gamma I, an Ornstein-Uhlenbeck
// process) and uniform shear flow in the Lees-Edwards frame (A = a e_x e_y^T, nilpotent), and any
// sum of them. gamma I commutes with the nilpotent part, so over a time s
//   exp(-A s) = e^{-gamma s} (I - a s e_x e_y^T),
// the mean map, and the covariance of the noise is
//   Sigma(s) = 2 beta int_0^s exp(-A u) exp(-A u)^T du
//            = 2 beta [I0 + a^2 I2 (xx), -a I1 (xy), I0 (yy, zz)],  I_m = int_0^s u^m e^{-2 gamma
//            u} du.
// Sampling it exactly makes the lazy update of a particle from its own last time exact for any s.
#include <cmath>

#include "granboltz/core/hot.hpp"
#include "granboltz/core/vec3.hpp"
#include "granboltz/random/samplers.hpp"

namespace granboltz {

/// g_m(x) = int_0^1 u^m e^{-x u} du for x >= 0, m = 0, 1, 2: I_m = s^{m+1} g_m(2 gamma s). The
/// series sum_k (-x)^k / (k! (m + k + 1)) below x = 1/2 for m = 1, 2 (where their closed forms
/// cancel), the closed forms above; m = 0 is (1 - e^{-x})/x with expm1 everywhere.
inline double exp_moment(int m, double x) {
  if (x == 0.0) return 1.0 / static_cast<double>(m + 1);  // no drag
  if (m == 0) return -std::expm1(-x) / x;                 // accurate at every x > 0
  if (x < 0.5) {
    double term = 1.0, sum = 0.0;
    for (int k = 0; k < 18; ++k) {  // 0.5^18/18! < 1e-21
      sum += term / static_cast<double>(m + k + 1);
      term *= -x / static_cast<double>(k + 1);
    }
    return sum;
  }
  const double e = std::exp(-x);
  switch (m) {
    case 1:
      return (1.0 - e * (1.0 + x)) / (x * x);
    default:
      return (2.0 - e * (2.0 + x * (2.0 + x))) / (x * x * x);
  }
}

/// The parameters of one linear flight: white-noise strength beta (the papers' heating), drag
/// (friction per unit time) gamma, and shear rate a.
struct LinearFlight {
  double beta = 0.0;
  double gamma = 0.0;
  double shear = 0.0;

  bool noisy() const { return beta > 0.0; }
  /// Anything but plain white noise: the engines' lazy kicks then use propagate().
  bool linear() const { return gamma != 0.0 || shear != 0.0; }

  /// The mean of v(s) given v(0) = v: exp(-A s) v.
  Vec3 mean(const Vec3& v, double s) const {
    const double d = gamma != 0.0 ? std::exp(-gamma * s) : 1.0;
    return {d * (v.x - shear * s * v.y), d * v.y, d * v.z};
  }

  /// The noise covariance over s: xx, xy, yy (= zz).
  struct Covariance {
    double xx, xy, yy;
  };
  Covariance covariance(double s) const {
    const double x = 2.0 * gamma * s;
    const double i0 = s * exp_moment(0, x);
    const double i1 = shear != 0.0 ? s * s * exp_moment(1, x) : 0.0;
    const double i2 = shear != 0.0 ? s * s * s * exp_moment(2, x) : 0.0;
    return {2.0 * beta * (i0 + shear * shear * i2), -2.0 * beta * shear * i1, 2.0 * beta * i0};
  }

  /// v(s) drawn exactly given v(0) = v, in D = 2 or 3 dimensions (z stays 0 in the plane).
  template <int D, class E>
  GRANBOLTZ_HOT Vec3 propagate(const Vec3& v, double s, E& eng) const {
    Vec3 m = mean(v, s);
    if (beta == 0.0 || s <= 0.0) return m;
    const Covariance c = covariance(s);
    // y first, then x given y (the Cholesky factor of the xy block).
    double zx, zy;
    normal_pair(eng, zy, zx);
    const double sy = std::sqrt(c.yy);
    const double cxy = c.xy / sy;
    m.y += sy * zy;
    m.x += cxy * zy + std::sqrt(std::max(c.xx - cxy * cxy, 0.0)) * zx;
    if constexpr (D == 3) m.z += sy * normal(eng);
    return m;
  }

  /// d<|v|^2>/dt of a particle with second moments <v v^T> = M (the energy rate the estimate and
  /// the docs use): 2 d beta - 2 gamma tr M - 2 a M_xy.
  double energy_rate(int d, double trace, double mxy) const {
    return 2.0 * d * beta - 2.0 * gamma * trace - 2.0 * shear * mxy;
  }
};

}  // namespace granboltz
