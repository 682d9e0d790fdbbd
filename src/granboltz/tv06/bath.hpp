#pragma once
// TV06 §3.1: the thermalized bath that an intruder collides with (bath particle mass m = 1).
//
// A bath is its velocity density f, its collision fluxes phi_+-(v1) on the two sides of a surface
// moving at v1 (TV06 eqs. 5-7) and an exact sampler of the velocity of the bath particle that
// collides with a given side (eqs. 12-13). Anything satisfying `IntruderBath` can drive the
// intruder. Baths with an even density are built from a standardized `Shape` p(y) (velocity
// v = scale * y), so that a new one needs only: p, its flux function k, two moments and three
// exact samplers (see docs/tv06.md, "Adding a bath").
//
// Notation in standardized units: k(c) = ∫_c^∞ (y - c) p(y) dy. For an even p with mean 0,
// k(-c) = k(c) + c, phi_-(v1) = rho scale k(v1/scale) and phi_+(v1) = rho scale k(-v1/scale).
// The colliding velocity on either side reduces to one "approach" density
//   q_c(y) = (y - c) p(y) / k(c),  y >= c,
// since g_-(v, v1) is q_c with c = v1/scale, and g_+(v, v1) is q_c of -v/scale with c = -v1/scale.
#include <algorithm>
#include <cmath>
#include <concepts>
#include <cstdint>

#include "granboltz/random/rng.hpp"
#include "granboltz/random/samplers.hpp"

namespace granboltz::tv06 {

/// The side of the intruder that a bath particle hits. kPlus: the side facing +x (+n for the
/// needle), hit by bath particles slower than the surface, v < v1 (TV06 eq. 5, "right hand
/// side"); kMinus: the side facing -x, hit by faster particles, v > v1 (eq. 6).
enum class Side { kPlus, kMinus };

/// Collision rates on both sides of a surface moving at v1 (TV06 eqs. 5-7).
struct Fluxes {
  double plus = 0.0;                             ///< phi_+(v1)
  double minus = 0.0;                            ///< phi_-(v1)
  double total() const { return plus + minus; }  ///< phi(v1), eq. 7
};

/// What the intruder simulations need from a bath.
template <class B>
concept IntruderBath = requires(const B& b, Engine& eng, double v, Side side) {
  { b.pdf(v) } -> std::convertible_to<double>;         ///< f(v)
  { b.temperature() } -> std::convertible_to<double>;  ///< T_B = <v^2> (mass 1, 1-D)
  { b.fluxes(v) } -> std::same_as<Fluxes>;             ///< phi_+-(v1), eqs. 5-6
  { b.sample(eng) } -> std::convertible_to<double>;    ///< exact draw from f
  { b.sample_colliding(eng, v, side) } -> std::convertible_to<double>;  ///< from g_+-, eqs. 12-13
};

// ---------------------------------------------------------------------------------------------
// Shapes: standardized even densities p(y) with mean 0.

/// p(y) = exp(-y^2/2) / sqrt(2 pi): the Gaussian bath of TV06 eq. 14 with y = v sqrt(2a).
struct GaussianShape {
  static constexpr double kHalfMoment = 0.398942280401432677940;  ///< k(0) = 1/sqrt(2 pi)
  static constexpr double kSecondMoment = 1.0;                    ///< ∫ y^2 p(y) dy

  static double pdf(double y) { return kHalfMoment * std::exp(-0.5 * y * y); }
  /// k(c) = phi(c) - c Q(c) for c >= 0 (Q: upper normal tail).
  static double tail_flux(double c);

  template <class E>
  static double sample(E& eng) {
    return normal(eng);
  }
  /// From y p(y) on y >= 0 (Rayleigh): inversion, y = sqrt(2 X) with X exponential.
  template <class E>
  static double sample_half_moment(E& eng) {
    return std::sqrt(2.0 * exponential(eng));
  }
  /// From q_c, c >= 0. With y = c + s the density is proportional to s exp(-c s - s^2/2): the
  /// proposal Gamma(2, lambda) (s = (X1 + X2)/lambda) is accepted with probability
  /// exp(-(s - lambda + c)^2 / 2); lambda = (c + sqrt(c^2 + 8))/2 maximises the acceptance,
  /// which is >= 0.73 for every c (and -> 1 as c grows).
  template <class E>
  static double sample_tail(E& eng, double c) {
    const double lambda = 0.5 * (c + std::sqrt(c * c + 8.0));
    const double shift = lambda - c;
    for (;;) {
      const double x1 = exponential(eng);
      const double x2 = exponential(eng);
      const double s = (x1 + x2) / lambda;
      const double r = s - shift;
      if (exponential(eng) >= 0.5 * r * r) return c + s;  // P(X >= r^2/2) = exp(-r^2/2)
    }
  }
};

/// p(y) = (sqrt 2 / pi) / (1 + y^4): the power-law bath of TV06 eq. 19 with y = v sqrt(a).
/// Its second moment is 1, so <v^2> = 1/a as TV06 states.
struct PowerLawShape {
  static constexpr double kNorm = 0.450158158078553034;           ///< sqrt(2)/pi
  static constexpr double kHalfMoment = 0.353553390593273762200;  ///< k(0) = sqrt(2)/4
  static constexpr double kSecondMoment = 1.0;
  /// Below this c the tail proposal y p(y) is the better one, above it (y - c)/y^4; they have
  /// the same acceptance (0.53) here, the worst over all c.
  static constexpr double kTailSwitch = 0.5;

  static double pdf(double y) {
    const double y2 = y * y;
    return kNorm / (1.0 + y2 * y2);
  }
  /// S(y) = ∫_y^∞ p, accurate in relative terms far in the tail (closed form and series).
  static double survival(double y);
  /// k(c) = ∫_c^∞ y p - c S(c) for c >= 0, with ∫_c^∞ y p = atan(1/c^2)/(sqrt(2) pi).
  static double tail_flux(double c);

  /// From p: rejection from the envelope 1 on [0, 1] and y^-4 beyond (masses 1 and 1/3,
  /// the second sampled as y = U^(-1/3)), acceptance pi/(2 sqrt 2)/(4/3) = 0.83; random sign.
  template <class E>
  static double sample(E& eng) {
    for (;;) {
      const std::uint64_t bits = eng();
      const bool negative = (bits & 1u) != 0;
      const bool core = ((bits >> 1) & 3u) != 0;  // probability 3/4
      double y, accept;
      if (core) {
        y = uniform01(eng);
        const double y2 = y * y;
        accept = 1.0 / (1.0 + y2 * y2);
      } else {
        const double w = std::cbrt(uniform_open01(eng));  // y = 1/w has density 3 y^-4 on y > 1
        y = 1.0 / w;
        const double w2 = w * w;
        accept = 1.0 / (1.0 + w2 * w2);  // = y^4 / (1 + y^4)
      }
      if (uniform01(eng) < accept) return negative ? -y : y;
    }
  }
  /// From y p(y) on y >= 0: t = y^2 has the half-Cauchy density 2/(pi (1 + t^2)), inverted.
  template <class E>
  static double sample_half_moment(E& eng) {
    return std::sqrt(std::tan(0.5 * M_PI * uniform01(eng)));
  }
  /// From q_c, c >= 0. For c < kTailSwitch: proposal y p(y) on y >= c (t = y^2 = cot(phi),
  /// phi uniform on (0, atan(1/c^2)]), accepted with probability (y - c)/y. Otherwise: proposal
  /// (y - c)/y^4 on y >= c, i.e. y = c/s with s ~ Beta(2, 2) (the median of three uniforms),
  /// accepted with probability y^4/(1 + y^4). Acceptance >= 0.53 for every c, -> 1 as c grows.
  template <class E>
  static double sample_tail(E& eng, double c) {
    if (c < kTailSwitch) {
      const double phi0 = std::atan2(1.0, c * c);
      for (;;) {
        const double y = std::sqrt(1.0 / std::tan(phi0 * uniform_open01(eng)));
        if (uniform01(eng) * y < y - c) return y;
      }
    }
    for (;;) {
      const double u1 = uniform_open01(eng);
      const double u2 = uniform_open01(eng);
      const double u3 = uniform_open01(eng);
      const double s = std::max(std::min(u1, u2), std::min(std::max(u1, u2), u3));  // median
      const double q = s / c;                                                       // 1/y
      const double q2 = q * q;
      if (uniform01(eng) * (1.0 + q2 * q2) < 1.0) return c / s;
    }
  }
};

/// k(c) for any real c (even shape with mean 0).
template <class Shape>
double approach_flux(double c) {
  return c >= 0 ? Shape::tail_flux(c) : Shape::tail_flux(-c) - c;
}

/// An exact draw from q_c(y) = (y - c) p(y) / k(c) on y >= c, for any real c.
/// c >= 0: the shape's tail sampler. c < 0: rejection from the envelope
/// y p(y) [y >= 0] + |c| p(y) (masses k(0) and |c|), which equals the target for y >= 0 and
/// exceeds it by the factor |c|/(y - c) on c < y < 0; acceptance k(c)/(k(0) + |c|) >= 0.77 for
/// both shapes.
template <class Shape, class E>
double sample_approach(E& eng, double c) {
  if (c >= 0) return Shape::sample_tail(eng, c);
  const double b = -c;
  const double pick_half = Shape::kHalfMoment / (Shape::kHalfMoment + b);
  for (;;) {
    if (uniform01(eng) < pick_half) return Shape::sample_half_moment(eng);
    const double y = Shape::sample(eng);
    if (y >= 0) return y;
    if (uniform01(eng) * b < y + b) return y;
  }
}

/// A bath with even density f(v) = p(v/scale)/scale and number density rho.
template <class Shape>
class SymmetricBath {
 public:
  SymmetricBath(double scale, double density) : scale_(scale), rho_(density) {}

  double scale() const { return scale_; }
  double density() const { return rho_; }
  double pdf(double v) const { return Shape::pdf(v / scale_) / scale_; }
  double temperature() const { return Shape::kSecondMoment * scale_ * scale_; }

  /// TV06 eqs. 5-6. The flux on the trailing side, k(|c|), is computed directly and the
  /// leading one as k(|c|) + |c|, so that neither loses digits.
  Fluxes fluxes(double v1) const {
    const double c = v1 / scale_;
    const double trailing = Shape::tail_flux(std::fabs(c));
    const double leading = trailing + std::fabs(c);
    const double unit = rho_ * scale_;
    return c >= 0 ? Fluxes{unit * leading, unit * trailing}
                  : Fluxes{unit * trailing, unit * leading};
  }

  template <class E>
  double sample(E& eng) const {
    return scale_ * Shape::sample(eng);
  }

  /// TV06 eqs. 12-13: the velocity of the bath particle hitting `side` of a surface at v1.
  template <class E>
  double sample_colliding(E& eng, double v1, Side side) const {
    const double c = v1 / scale_;
    return side == Side::kPlus ? -scale_ * sample_approach<Shape>(eng, -c)
                               : scale_ * sample_approach<Shape>(eng, c);
  }

 private:
  double scale_, rho_;
};

using GaussianBath = SymmetricBath<GaussianShape>;
using PowerLawBath = SymmetricBath<PowerLawShape>;

/// TV06 eq. 14: f = sqrt(a/pi) exp(-a v^2), T_B = 1/(2a).
inline GaussianBath gaussian_bath(double a, double density) {
  return GaussianBath(1.0 / std::sqrt(2.0 * a), density);
}
/// TV06 eq. 19: f = sqrt(2a)/pi / (1 + a^2 v^4), T_B = <v^2> = 1/a.
inline PowerLawBath power_law_bath(double a, double density) {
  return PowerLawBath(1.0 / std::sqrt(a), density);
}

static_assert(IntruderBath<GaussianBath>);
static_assert(IntruderBath<PowerLawBath>);

}  // namespace granboltz::tv06
