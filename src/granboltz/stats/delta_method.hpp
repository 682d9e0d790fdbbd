#pragma once
// Intervals of functions of ensemble means by the delta method: a ratio of two means (theta,
// T_a/T_b) and the Sonine coefficients a2, a3 from the speed moments M2, M4, M6.
#include <cstdint>

#include "granboltz/stats/statistics.hpp"

namespace granboltz {

/// r = mu_x/mu_y of the ensemble means and its variance by the delta method, (V_x - 2 r C_xy +
/// r^2 V_y)/(mu_y^2 N), with the (co)variances of (x, y) over the N ensembles (population: the
/// series, as their ci; sample, N - 1: the steady averages, as /steady); written so that mu_x = 0
/// (T_rot(0) = 0) gives 0, not 0/0. bias: the leading 1/N bias of a ratio of means, (r V_y -
/// C_xy)/(mu_y^2 N) (second-order delta method). Only xy.sum is read.
struct RatioStats {
  double mean = 0.0, variance = 0.0, bias = 0.0;
};
RatioStats ratio_of_means(double mean_x, double mean_y, const Moments2& x, const Moments2& y,
                          const Moments2& xy, std::uint64_t N, bool sample_covariance);

/// The pairs of speed moments whose cross sums the Sonine intervals need: (M2, M4), then with
/// P >= 3 (M2, M6), (M4, M6).
inline std::uint64_t cross_pairs(std::uint64_t P) { return P >= 3 ? 3 : P == 2 ? 1 : 0; }
/// Adds the products of the cross_pairs(P) pairs of M = (M2, M4, M6) of one sample to out[].sum.
void add_cross(Moments2* out, const double* M, std::uint64_t P);

/// a2 = d/(d+2) M4/M2^2 - 1 and a3 = 1 + 3 a2 - d^2/((d+2)(d+4)) M6/M2^3 at the ensemble
/// means of M2, M4, M6, and their variances by the delta method, g^T Cov g / N with the
/// covariance of the ensembles' (M2, M4, M6): a ratio of means, not a mean of ratios, so that
/// neither is biased by the noise of one ensemble's M2.
/// bias_*: the ratio estimator's leading bias, (1/2) tr(H Cov) / N with H the Hessian of a2 or
/// a3 in the moments (second-order delta method); O(1/N) against a sigma of O(1/sqrt(N)).
struct Sonine {
  double a2 = 0.0, a3 = 0.0, var_a2 = 0.0, var_a3 = 0.0, bias_a2 = 0.0, bias_a3 = 0.0;
};
/// M[0..P): the sums of M2, M4 (, M6) over N samples; cross: their add_cross sums. a3 with P >= 3.
Sonine sonine(const Moments2* M, const Moments2* cross, std::uint64_t P, std::uint64_t N,
              bool sample_covariance, int dimension);

}  // namespace granboltz
