#pragma once
// TV06 §3.2: a needle (uniform rod of mass M, length L, I = M L^2/12) moving in the plane through
// a Gaussian bath of point particles of mass 1. Kernels: the total collision rate Phi (eqs. 21-22
// of the pdf text), the impact point and collision rule (eqs. 25-29), and the two ways of drawing
// the waiting time of eq. 23. The event loop runs one ensemble.
#include <gsl/gsl_integration.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "granboltz/exec/ensemble_pool.hpp"
#include "granboltz/tv06/bath.hpp"
#include "granboltz/tv06/config.hpp"
#include "granboltz/tv06/observe.hpp"

namespace granboltz::tv06 {

struct NeedleBody {
  double mass = 1.0, length = 1.0, inertia = 1.0 / 12.0;
};
/// A uniform rod: I = M L^2 / 12.
inline NeedleBody uniform_rod(double mass, double length) {
  return {mass, length, mass * length * length / 12.0};
}

/// Centre-of-mass velocity, angular velocity, and orientation theta of the needle's axis
/// e = (cos theta, sin theta). The normal is n = (-sin theta, cos theta) (TV06 Fig. 6), so the
/// point at distance x along the axis moves with normal velocity v_n + omega x.
struct NeedleState {
  double vx = 0.0, vy = 0.0, omega = 0.0, theta = 0.0;
};

/// TV06 eq. 20: v_n = v1 . n = v1y cos theta - v1x sin theta.
inline double normal_velocity(const NeedleState& s) {
  return s.vy * std::cos(s.theta) - s.vx * std::sin(s.theta);
}

/// The total collision rate Phi(v_n, omega) = ∫_{-L/2}^{L/2} phi(v_n + omega x) dx (eq. 21) of a
/// needle in a Gaussian bath. Closed form for any a and L, generalising eq. 22 (a = L = 1):
/// with phi(w) = rho sigma g(w/sigma), sigma = 1/sqrt(2a), g(z) = 2 phi_N(z) + z erf(z/sqrt 2)
/// and its antiderivative G(z) = (z^2 + 1) erf(z/sqrt 2)/2 + z phi_N(z),
///   Phi = rho sigma L [G(zeta + tau) - G(zeta - tau)] / (2 tau),
/// zeta = v_n/sigma, tau = omega L/(2 sigma). The difference cancels as tau -> 0; there the
/// midpoint series g(zeta) + 2 phi_N(zeta) sum_j tau^(2j) He_(2j-2)(zeta)/(2j+1)! is used.
class NeedleRate {
 public:
  NeedleRate(const GaussianBath& bath, double length)
      : bath_(bath), sigma_(bath.scale()), rho_(bath.density()), length_(length) {}

  const GaussianBath& bath() const { return bath_; }
  double length() const { return length_; }
  /// phi(w): both sides' rate per unit length at a point of normal velocity w (eq. 16).
  double per_length(double w) const { return bath_.fluxes(w).total(); }
  /// Phi(v_n, omega), eqs. 21-22.
  double operator()(double vn, double omega) const;
  /// Phi is even and convex in v_n (phi is, and the needle is symmetric about its centre), so
  /// along a free rotation, where |v_n| <= |v1|, it lies between these two (with a margin of
  /// 1e-12 for rounding).
  double upper_bound(double speed, double omega) const {
    return (*this)(speed, omega) * (1.0 + 1e-12);
  }
  double lower_bound(double omega) const { return (*this)(0.0, omega) * (1.0 - 1e-12); }

 private:
  GaussianBath bath_;
  double sigma_, rho_, length_;
};

/// TV06 eq. 29: the impulse along n on the needle, Delta p = -(1+alpha) g.n / (1/m + 1/M +
/// x^2/I), with g.n = (v_n + omega x) - v the normal relative velocity of the contact point and
/// the bath particle (normal velocity v, mass m = 1). The tangential velocity of the bath
/// particle does not enter: the needle is smooth.
inline double needle_impulse(const NeedleBody& b, double alpha, double x, double contact_velocity,
                             double v) {
  return -(1.0 + alpha) * (contact_velocity - v) / (1.0 + 1.0 / b.mass + x * x / b.inertia);
}

/// TV06 eqs. 27-28: v1' = v1 + n Delta p / M, I omega' = I omega + x Delta p.
/// The bath particle receives -n Delta p.
inline void apply_needle_impulse(NeedleState& s, const NeedleBody& b, double x, double dp) {
  const double nx = -std::sin(s.theta), ny = std::cos(s.theta);
  s.vx += nx * dp / b.mass;
  s.vy += ny * dp / b.mass;
  s.omega += x * dp / b.inertia;
}

/// The impact point, from p(x|t) ∝ phi(v_n + omega x) on [-L/2, L/2] (eq. 25), by rejection
/// from the uniform density under the maximum of phi, which is at an end since phi is convex.
/// Also returns the side fluxes at the chosen point, for eq. 26.
template <class E>
double sample_impact_point(const NeedleRate& rate, double vn, double omega, E& eng,
                           Fluxes* at_point) {
  const double h = 0.5 * rate.length();
  const double top =
      std::max(rate.per_length(vn + omega * h), rate.per_length(vn - omega * h)) * (1.0 + 1e-12);
  for (;;) {
    const double x = h * (2.0 * uniform01(eng) - 1.0);
    const Fluxes f = rate.bath().fluxes(vn + omega * x);
    if (uniform01(eng) * top < f.total()) {
      *at_point = f;
      return x;
    }
  }
}

/// The waiting time of eq. 23 by thinning (Lewis and Shedler 1979): candidates at the constant
/// rate Phi_max = Phi(|v1|, omega) >= Phi(t), each accepted with probability Phi(t)/Phi_max.
/// The accepted time has exactly the law P(T > t) = exp(-∫_0^t Phi). `rejected` counts the
/// fictitious candidates.
template <class E>
double waiting_time_by_thinning(const NeedleRate& rate, const NeedleState& s, E& eng,
                                std::uint64_t* rejected) {
  const double bound = rate.upper_bound(std::hypot(s.vx, s.vy), s.omega);
  double t = 0.0;
  for (;;) {
    t += exponential(eng) / bound;
    const double angle = s.theta + s.omega * t;
    const double vn = s.vy * std::cos(angle) - s.vx * std::sin(angle);
    if (uniform01(eng) * bound < rate(vn, s.omega)) return t;
    ++*rejected;
  }
}

/// The waiting time of eq. 23 by inversion, as TV06 do: solve ∫_0^t Phi(t') dt' = -ln xi. The
/// integral is done by adaptive Gauss-Kronrod quadrature (GSL qag) from the nearest point
/// already integrated, and the root by Brent's method (GSL) on the bracket
/// [E/Phi_max, E/Phi_min], which always holds the root since Phi_min <= Phi(t) <= Phi_max:
/// no Newton step can escape, and no doubling search is needed.
class WaitingTimeSolver {
 public:
  explicit WaitingTimeSolver(const NeedleRate& rate);
  ~WaitingTimeSolver();
  WaitingTimeSolver(const WaitingTimeSolver&) = delete;
  WaitingTimeSolver& operator=(const WaitingTimeSolver&) = delete;

  /// The t > 0 with ∫_0^t Phi = target, for the free rotation starting from s.
  double solve(const NeedleState& s, double target);
  /// ∫_0^t Phi(t') dt' for the free rotation starting from s (no caching).
  double integral(const NeedleState& s, double t);
  /// Evaluations of Phi so far.
  std::uint64_t rate_evaluations() const { return evaluations_; }

  template <class E>
  double sample(const NeedleState& s, E& eng) {
    return solve(s, exponential(eng));
  }

 private:
  /// qag subintervals: enough for thousands of turns of the needle within one waiting time.
  static constexpr std::size_t kWorkspace = 4096;
  static constexpr double kRelativeTolerance = 1e-11;  ///< of each quadrature
  /// Brackets longer than this many half-turns are solved by whole half-turns (solve()).
  static constexpr double kManyHalfTurns = 1e4;

  double rate_at(double t) const;
  /// ∫_a^b Phi by qag into *result; GSL's status.
  int integrate(double a, double b, double* result);
  /// ∫_0^t from the nearest cached point; NaN (and failure_ set) if the quadrature fails.
  double cumulative(double t);
  /// Brent's root of cumulative(t) = target in [lo, hi]; GSL's status (or the quadrature's).
  int find_root(double target, double lo, double hi, double* root);
  double solve_by_half_turns(double target, double half_turn, double hi_rate, double lo_rate);
  std::string failure_message(int status) const;

  const NeedleRate& rate_;
  NeedleState state_;
  gsl_integration_workspace* workspace_;
  std::vector<std::pair<double, double>> known_;  // (t, ∫_0^t Phi) of this solve
  std::uint64_t evaluations_ = 0;
  int failure_ = 0;  // first failed quadrature status of the current root search
};

/// The time averages and counts of one ensemble of a needle run.
struct NeedleEnsemble {
  double translational_ratio = 0.0;  ///< T_trans/T_B, T_trans = M <|v1|^2> / 2
  double rotational_ratio = 0.0;     ///< T_rot/T_B, T_rot = I <omega^2>
  double R = 0.0;                    ///< <v^2 omega^2> / (<v^2> <omega^2>), eq. 30
  std::uint64_t samples = 0, collisions = 0;
  std::uint64_t fictitious = 0;  ///< thinning: rejected candidate times
  double time = 0.0;             ///< simulated time after the warm-up
  std::uint64_t draws = 0;       ///< raw random numbers drawn (benchmark floor)
  Histogram velocity_histogram;  ///< of v1x
  Histogram omega_histogram;     ///< of omega
};

/// The sampling interval: `sample_every`, or the mean free time 1/Phi(0, 0) when it is 0.
double needle_sample_interval(const NeedleConfig& c);

/// Runs ensemble `ensemble` of a needle config; the needle starts at rest.
NeedleEnsemble simulate_needle(const NeedleConfig& c, std::uint64_t seed, std::uint64_t ensemble,
                               ProgressSlot* slot = nullptr);

}  // namespace granboltz::tv06
