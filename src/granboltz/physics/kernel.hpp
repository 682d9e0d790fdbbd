#pragma once
// The variable hard sphere kernel B = C_lambda |u|^lambda, 0 <= lambda <= 1 (GRW05 eq. 8),
// with the collision-term prefactor gamma of GRW05 eq. (1).
#include <cmath>

namespace granboltz {

struct VhsKernel {
  double lambda = 0.0;  ///< 0: Maxwell pseudo-molecules, 1: hard spheres
  double C = 1.0;       ///< C_lambda
  double gamma = 1.0;   ///< prefactor of the collision term
  /// |S^{d-1}| = 4 pi (d = 3) or 2 pi (d = 2): B is C |u|^lambda per unit of solid angle, so the
  /// loss rate of a particle is area gamma C <|v - w|^lambda>.
  double area = 4.0 * M_PI;

  /// s^lambda without pow() for the common cases lambda = 0 and lambda = 1.
  double power(double s) const {
    if (lambda == 0.0) return 1.0;
    if (lambda == 1.0) return s;
    if (lambda == 0.5) return std::sqrt(s);
    return std::pow(s, lambda);
  }

  /// Total rate of the majorant process for n particles and maximal relative speed u_max:
  /// pi_hat = 2 pi gamma C (n - 1) u_max^lambda (GRW05 §4, RW05 eq. 20) in d = 3, with area/2 for
  /// 2 pi in d dimensions.
  double majorant_rate(double n, double u_max) const {
    return 0.5 * area * gamma * C * (n - 1.0) * power(u_max);
  }

  /// Probability that a candidate pair with relative speed u is a real collision, given the
  /// majorant u_max: (u/u_max)^lambda, and 1 when u > u_max (the truncated kernel, RW05 eq. 19).
  double acceptance(double u, double u_max) const {
    if (lambda == 0.0 || u >= u_max) return 1.0;
    return power(u / u_max);
  }
};

}  // namespace granboltz
