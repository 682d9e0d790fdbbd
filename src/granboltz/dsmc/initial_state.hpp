#pragma once
// Prepared initial states (dsmc.initial): the anisotropic Maxwellian of a temperature tensor and
// a skewed state with a prescribed heat flux.
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <vector>

#include "granboltz/core/vec3.hpp"
#include "granboltz/random/samplers.hpp"

namespace granboltz {

/// The lower Cholesky factor L of a symmetric d x d temperature tensor T (T = L L^T), row-major
/// 3 x 3 with zeros beyond d; none if T is not positive definite (a pivot <= 0 or not finite).
inline std::optional<std::array<double, 9>> temperature_factor(const std::vector<double>& T,
                                                               int d) {
  std::array<double, 9> L{};
  for (int i = 0; i < d; ++i)
    for (int j = 0; j <= i; ++j) {
      double s = T[static_cast<std::size_t>(i * d + j)];
      for (int k = 0; k < j; ++k) s -= L[3 * i + k] * L[3 * j + k];
      if (i == j) {
        if (!(s > 0) || !std::isfinite(s)) return std::nullopt;
        L[3 * i + i] = std::sqrt(s);
      } else {
        L[3 * i + j] = s / L[3 * j + j];
      }
    }
  return L;
}

/// One velocity of the anisotropic Maxwellian with covariance scale^2 L L^T: d standard normals
/// drawn in order (z), then scale L z; v_z = 0 in d = 2.
template <class E>
inline Vec3 anisotropic_velocity(const std::array<double, 9>& L, int d, double scale, E& eng) {
  const double a = normal(eng);
  const double b = normal(eng);
  const double c = d == 3 ? normal(eng) : 0.0;
  return {scale * L[0] * a, scale * (L[3] * a + L[4] * b),
          scale * (L[6] * a + L[7] * b + L[8] * c)};
}

/// The skewed state of dsmc.initial.heat_flux, in the reduced velocity x = c / sqrt(T/m):
///   f(x) = f_M(x) [1 + phi(x)],  phi(x) = (g.x) (|x|^2 - K) exp(-|x|^2/2),  K = (d + 2)/2.
/// phi is odd, so every even moment (density, temperature tensor, fourth moment) is the
/// Maxwellian's; K makes the momentum zero (E_M[x x^T (|x|^2 - K) e^{-|x|^2/2}] = 0), and the
/// heat flux q = (1/2) <w |w|^2> of w = sqrt(m) c (the output's heat_flux; m <c |c|^2>/2 for
/// unit mass) is heat_flux_gain(d) T^{3/2} g, the same for every mass, with
/// heat_flux_gain = (d + 2) 2^{-d/2} / 8 (Gaussian integrals against the weight e^{-|x|^2/2}).
/// The density stays positive iff |g| H < 1, H = max_r |r (r^2 - K) e^{-r^2/2}| (heat_flux_peak).
struct SkewedState {
  Vec3 g;           ///< the reduced flux vector (0 beyond d)
  double envelope;  ///< 1 + |g| H >= 1 + phi: the rejection envelope

  /// phi(x) of the state.
  double phi(const Vec3& x, int d) const {
    const double r2 = norm2(x);
    return dot(g, x) * (r2 - 0.5 * (d + 2)) * std::exp(-0.5 * r2);
  }
};

/// (d + 2) 2^{-d/2} / 8: q = gain T^{3/2} g.
inline double heat_flux_gain(int d) { return (d + 2) * std::pow(2.0, -0.5 * d) / 8.0; }

/// H = max_{r >= 0} |r (r^2 - K) e^{-r^2/2}|, K = (d + 2)/2: at a root of
/// r^4 - (3 + K) r^2 + K = 0 (1.1014 in d = 3, 0.8304 in d = 2: the inner extremum; so
/// |q| < 0.2006 T^{3/2} in d = 3, 0.3010 T^{3/2} in d = 2).
inline double heat_flux_peak(int d) {
  const double K = 0.5 * (d + 2), b = 3.0 + K, disc = std::sqrt(b * b - 4.0 * K);
  double h = 0.0;
  for (const double r2 : {0.5 * (b - disc), 0.5 * (b + disc)})
    h = std::max(h, std::fabs(std::sqrt(r2) * (r2 - K) * std::exp(-0.5 * r2)));
  return h;
}

/// The largest |q| a positive density allows at temperature T.
inline double max_heat_flux(int d, double T) {
  return heat_flux_gain(d) * std::pow(T, 1.5) / heat_flux_peak(d);
}

/// The state of heat flux q at temperature T (|q| < max_heat_flux, checked by the config).
inline SkewedState skewed_state(const std::vector<double>& q, int d, double T) {
  const double s = 1.0 / (heat_flux_gain(d) * std::pow(T, 1.5));
  SkewedState st{{s * q[0], s * q[1], d == 3 ? s * q[2] : 0.0}, 1.0};
  st.envelope = 1.0 + norm(st.g) * heat_flux_peak(d);
  return st;
}

/// One velocity of the skewed state (exact rejection against the Maxwellian times the bounded
/// envelope; acceptance 1/envelope >= 1/2): x drawn as anisotropic_velocity's z, then a uniform.
template <class E>
inline Vec3 skewed_velocity(const SkewedState& st, int d, double sd, E& eng) {
  for (;;) {
    const double a = normal(eng);
    const double b = normal(eng);
    const double c = d == 3 ? normal(eng) : 0.0;
    const Vec3 x{a, b, c};
    if (uniform01(eng) * st.envelope < 1.0 + st.phi(x, d)) return sd * x;
  }
}

/// What dsmc.initial prepares beyond the isotropic Maxwellian of T0, made once per ensemble.
struct PreparedStart {
  std::optional<std::array<double, 9>> tensor;  // the Cholesky factor of the temperature tensor
  std::optional<SkewedState> skew;
  int d = 3;
  double T0 = 1.0;
  /// A velocity of a particle of mass m, or none for the isotropic Maxwellian, which each
  /// engine draws as it always has (its bits).
  template <class E>
  std::optional<Vec3> velocity(double m, E& eng) const {
    if (tensor) return anisotropic_velocity(*tensor, d, 1.0 / std::sqrt(m), eng);
    if (skew) return skewed_velocity(*skew, d, std::sqrt(T0 / m), eng);
    return std::nullopt;
  }
};

/// The start of the config's temperature tensor and heat flux (empty: not given; both checked
/// by the config).
inline PreparedStart prepared_start(const std::vector<double>& tensor,
                                    const std::vector<double>& heat_flux, int d, double T0) {
  PreparedStart s;
  s.d = d;
  s.T0 = T0;
  if (!tensor.empty()) s.tensor = temperature_factor(tensor, d);
  if (!heat_flux.empty()) s.skew = skewed_state(heat_flux, d, T0);
  return s;
}

}  // namespace granboltz
