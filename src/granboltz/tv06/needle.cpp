// The needle of TV06 §3.2: total rate, waiting-time inversion, and the event loop of one ensemble.
#include "granboltz/tv06/needle.hpp"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_roots.h>
#include <gsl/gsl_sf_erf.h>

#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>

#include "granboltz/core/gsl_errors.hpp"
#include "granboltz/random/rng.hpp"

namespace granboltz::tv06 {

namespace {

constexpr double kInvSqrt2 = 0.70710678118654752440;
constexpr double kInvSqrt2Pi = 0.398942280401432677940;
/// Below tau (1 + |zeta|) = 0.5 the series of NeedleRate is used: there its 10 terms are exact
/// to 1e-20, while above it the closed form loses at most a factor ~(1 + |zeta|)^2 to cancellation.
constexpr double kSeriesBelow = 0.5;
constexpr int kSeriesTerms = 10;

double normal_pdf(double z) { return kInvSqrt2Pi * std::exp(-0.5 * z * z); }

/// g(z) = phi(sigma z)/(rho sigma) = ∫ |z - y| p_N(y) dy.
double unit_rate(double z) { return 2.0 * normal_pdf(z) + z * gsl_sf_erf(z * kInvSqrt2); }

/// G(z) = ∫_0^z g: G' = z erf(z/sqrt2) + (z^2+1) p_N(z) + (1 - z^2) p_N(z) = g.
double unit_rate_integral(double z) {
  return 0.5 * (z * z + 1.0) * gsl_sf_erf(z * kInvSqrt2) + z * normal_pdf(z);
}

/// (1/(2 tau)) ∫_{-tau}^{tau} g(zeta + s) ds.
double mean_unit_rate(double zeta, double tau) {
  const double t = std::fabs(tau);
  if (t * (1.0 + std::fabs(zeta)) >= kSeriesBelow)
    return (unit_rate_integral(zeta + t) - unit_rate_integral(zeta - t)) / (2.0 * t);
  // Midpoint series: g'' = 2 p_N and p_N^(2k) = He_2k p_N (probabilists' Hermite polynomials).
  const double t2 = t * t;
  double he = 1.0, he_next = zeta;  // He_n, He_(n+1) for n = 2j - 2
  double coef = t2 / 6.0;           // tau^(2j) / (2j+1)!
  double sum = coef;
  for (int j = 2, n = 0; j <= kSeriesTerms; ++j, n += 2) {
    const double he2 = zeta * he_next - (n + 1) * he;
    const double he3 = zeta * he2 - (n + 2) * he_next;
    he = he2;
    he_next = he3;
    coef *= t2 / ((2.0 * j) * (2.0 * j + 1.0));
    sum += coef * he;
  }
  return unit_rate(zeta) + 2.0 * normal_pdf(zeta) * sum;
}

constexpr double kPi = 3.141592653589793238463;
constexpr double kTwoPi = 6.283185307179586476925;
constexpr std::uint64_t kProgressEvery = 1u << 14;

}  // namespace

double NeedleRate::operator()(double vn, double omega) const {
  const double zeta = vn / sigma_;
  const double tau = 0.5 * omega * length_ / sigma_;
  return rho_ * sigma_ * length_ * mean_unit_rate(zeta, tau);
}

// ---------------------------------------------------------------------------------------------

WaitingTimeSolver::WaitingTimeSolver(const NeedleRate& rate) : rate_(rate), workspace_(nullptr) {
  install_gsl_error_handler();
  workspace_ = gsl_integration_workspace_alloc(kWorkspace);
  if (!workspace_) throw std::bad_alloc();
}

WaitingTimeSolver::~WaitingTimeSolver() { gsl_integration_workspace_free(workspace_); }

double WaitingTimeSolver::rate_at(double t) const {
  const double angle = state_.theta + state_.omega * t;
  const double vn = state_.vy * std::cos(angle) - state_.vx * std::sin(angle);
  return rate_(vn, state_.omega);
}

int WaitingTimeSolver::integrate(double a, double b, double* result) {
  if (a == b) {
    *result = 0.0;
    return GSL_SUCCESS;
  }
  if (b < a) {
    const int status = integrate(b, a, result);
    *result = -*result;
    return status;
  }
  struct Ctx {
    WaitingTimeSolver* self;
  } ctx{this};
  gsl_function f;
  f.function = [](double t, void* p) {
    auto* c = static_cast<Ctx*>(p);
    ++c->self->evaluations_;
    return c->self->rate_at(t);
  };
  f.params = &ctx;
  double error = 0.0;
  // Phi > 0 is smooth: relative accuracy 1e-11 is reached without round-off trouble.
  return gsl_integration_qag(&f, a, b, 0.0, kRelativeTolerance, kWorkspace, GSL_INTEG_GAUSS31,
                             workspace_, result, &error);
}

double WaitingTimeSolver::cumulative(double t) {
  const std::pair<double, double>* nearest = &known_.front();
  for (const auto& k : known_)
    if (std::fabs(k.first - t) < std::fabs(nearest->first - t)) nearest = &k;
  double part = 0.0;
  const int status = integrate(nearest->first, t, &part);
  if (status != GSL_SUCCESS) {
    // Called from inside GSL's root finder, where no exception may be thrown: record the
    // failure and hand GSL a value it refuses (it then returns an error status).
    if (failure_ == GSL_SUCCESS) failure_ = status;
    return std::numeric_limits<double>::quiet_NaN();
  }
  const double value = nearest->second + part;
  known_.emplace_back(t, value);
  return value;
}

double WaitingTimeSolver::integral(const NeedleState& s, double t) {
  state_ = s;
  double result = 0.0;
  const int status = integrate(0.0, t, &result);
  if (status != GSL_SUCCESS)
    throw std::runtime_error("needle waiting time: quadrature failed: " +
                             describe_gsl_status(status));
  return result;
}

int WaitingTimeSolver::find_root(double target, double lo, double hi, double* root) {
  failure_ = GSL_SUCCESS;
  // The bounds' margin (1e-12) is below the quadrature's tolerance: if an end does not straddle
  // the root within that tolerance, it is the root (and GSL must never see such a bracket).
  const double at_lo = cumulative(lo);
  if (failure_ != GSL_SUCCESS) return failure_;
  if (at_lo >= target) {
    *root = lo;
    return GSL_SUCCESS;
  }
  const double at_hi = cumulative(hi);
  if (failure_ != GSL_SUCCESS) return failure_;
  if (at_hi <= target) {
    *root = hi;
    return GSL_SUCCESS;
  }

  struct Ctx {
    WaitingTimeSolver* self;
    double target;
  } ctx{this, target};
  gsl_function f;
  f.function = [](double t, void* p) {
    auto* c = static_cast<Ctx*>(p);
    return c->self->cumulative(t) - c->target;
  };
  f.params = &ctx;
  gsl_root_fsolver* solver = gsl_root_fsolver_alloc(gsl_root_fsolver_brent);
  if (!solver) throw std::bad_alloc();
  *root = 0.5 * (lo + hi);
  int status = gsl_root_fsolver_set(solver, &f, lo, hi);
  for (int iter = 0; status == GSL_SUCCESS && iter < 200; ++iter) {
    status = gsl_root_fsolver_iterate(solver);
    *root = gsl_root_fsolver_root(solver);
    lo = gsl_root_fsolver_x_lower(solver);
    hi = gsl_root_fsolver_x_upper(solver);
    // The quadrature is good to 1e-11: a tighter root would only chase its rounding.
    if (gsl_root_test_interval(lo, hi, 0.0, 1e-12) == GSL_SUCCESS) break;
  }
  gsl_root_fsolver_free(solver);
  return failure_ != GSL_SUCCESS ? failure_ : status;
}

double WaitingTimeSolver::solve(const NeedleState& s, double target) {
  state_ = s;
  known_.clear();
  known_.emplace_back(0.0, 0.0);
  const double hi_rate = rate_.upper_bound(std::hypot(s.vx, s.vy), s.omega);
  const double lo_rate = rate_.lower_bound(s.omega);
  const double lo = target / hi_rate, hi = target / lo_rate;
  if (hi - lo <= 1e-15 * hi) return 0.5 * (lo + hi);  // Phi constant (v1 = 0)
  // Phi(t) has the period of half a turn (Phi is even in v_n). Over many turns one quadrature
  // over the whole bracket would need more subintervals than qag has, so then the whole
  // half-turns are counted and only the remainder is solved for. Below kManyHalfTurns (and
  // whenever it succeeds) the direct solve is kept: its results are the published ones.
  const double half_turn = s.omega != 0.0 ? kPi / std::fabs(s.omega) : 0.0;
  const bool periodic = half_turn > 0.0 && std::isfinite(half_turn);
  double root = 0.0;
  int status = GSL_SUCCESS;
  if (!periodic || hi <= kManyHalfTurns * half_turn) {
    status = find_root(target, lo, hi, &root);
    if (status == GSL_SUCCESS) return root;
    if (!periodic) throw std::runtime_error(failure_message(status));
  }
  return solve_by_half_turns(target, half_turn, hi_rate, lo_rate);
}

double WaitingTimeSolver::solve_by_half_turns(double target, double half_turn, double hi_rate,
                                              double lo_rate) {
  known_.clear();
  known_.emplace_back(0.0, 0.0);
  double per_half_turn = 0.0;
  int status = integrate(0.0, half_turn, &per_half_turn);
  if (status != GSL_SUCCESS) throw std::runtime_error(failure_message(status));
  // The phase after k half-turns is the start's again, so the cache of [0, half_turn] serves.
  known_.emplace_back(half_turn, per_half_turn);
  const double turns = std::floor(target / per_half_turn);
  const double rest = std::clamp(target - turns * per_half_turn, 0.0, per_half_turn);
  if (rest == 0.0) return turns * half_turn;
  const double lo = std::min(rest / hi_rate, half_turn);
  const double hi = std::min(rest / lo_rate, half_turn);
  double root = 0.0;
  status = lo < hi ? find_root(rest, lo, hi, &root) : (root = lo, GSL_SUCCESS);
  if (status != GSL_SUCCESS) throw std::runtime_error(failure_message(status));
  return turns * half_turn + root;
}

std::string WaitingTimeSolver::failure_message(int status) const {
  return "needle waiting time: the inversion did not converge (" + describe_gsl_status(status) +
         ")";
}

// ---------------------------------------------------------------------------------------------

double needle_sample_interval(const NeedleConfig& c) {
  if (c.sample_every > 0) return c.sample_every;
  return 1.0 / NeedleRate(gaussian_bath(c.a, c.density), c.length)(0.0, 0.0);
}

namespace {

/// Time averages of |v1|^2, omega^2 and their product at equal intervals (TV06 §3.1 step 2).
class NeedleAverages {
 public:
  NeedleAverages(const NeedleConfig& c, double dt)
      : vel_(c.velocity_histogram), omega_(c.omega_histogram), dt_(dt) {}
  void start(double t) {
    clock_.start(t, dt_, "needle.sample_every");
    t0_ = t;
  }
  void advance(double t, const NeedleState& s) {
    const std::uint64_t n = clock_.count_before(t);
    if (n == 0) return;
    const double w = static_cast<double>(n);
    const double v2 = s.vx * s.vx + s.vy * s.vy, o2 = s.omega * s.omega;
    v2_.add(w * v2);
    o2_.add(w * o2);
    v2o2_.add(w * v2 * o2);
    vel_.add(s.vx, n);
    omega_.add(s.omega, n);
    samples_ += n;
  }
  void finish(double t, const NeedleBody& body, double bath_temperature, NeedleEnsemble* r) {
    if (samples_ == 0)
      throw std::runtime_error(
          "needle: no sample time fell inside the run; increase collisions or decrease "
          "sample_every");
    const double n = static_cast<double>(samples_);
    const double v2 = v2_.value() / n, o2 = o2_.value() / n, v2o2 = v2o2_.value() / n;
    r->translational_ratio = 0.5 * body.mass * v2 / bath_temperature;
    r->rotational_ratio = body.inertia * o2 / bath_temperature;
    r->R = v2o2 / (v2 * o2);
    // Extreme but valid scales (a needle far heavier or lighter than the bath) can leave the
    // averages outside double precision; say so with the config, rather than as a bare NaN.
    if (!std::isfinite(r->translational_ratio) || !std::isfinite(r->rotational_ratio) ||
        !std::isfinite(r->R)) {
      char what[200];
      std::snprintf(what, sizeof what,
                    "needle.mass = %.6g: non-finite value of T_trans, T_rot or R (length = %.6g, "
                    "a = %.6g): the averages over- or underflow in double precision",
                    body.mass, body.length, 1.0 / (2.0 * bath_temperature));
      throw std::runtime_error(what);
    }
    r->samples = samples_;
    r->time = t - t0_;
    r->velocity_histogram = std::move(vel_);
    r->omega_histogram = std::move(omega_);
  }

 private:
  SampleClock clock_;
  CompensatedSum v2_, o2_, v2o2_;
  Histogram vel_, omega_;
  double dt_, t0_ = 0.0;
  std::uint64_t samples_ = 0;
};

}  // namespace

namespace {

// The solver's failure, with the config that led to it (the solver knows only the rate).
double sample_by_inversion(WaitingTimeSolver& solver, const NeedleState& s, Engine& eng,
                           const NeedleConfig& c) {
  try {
    return solver.sample(s, eng);
  } catch (const std::runtime_error& e) {
    char where[160];
    std::snprintf(where, sizeof where,
                  "needle.waiting_time = inversion (mass = %.6g, length = %.6g, "
                  "density = %.6g, a = %.6g): ",
                  c.mass, c.length, c.density, c.a);
    throw std::runtime_error(where + std::string(e.what()) + "; use waiting_time: thinning");
  }
}

}  // namespace

NeedleEnsemble simulate_needle(const NeedleConfig& c, std::uint64_t seed, std::uint64_t ensemble,
                               ProgressSlot* slot) {
  const GaussianBath bath = gaussian_bath(c.a, c.density);
  const NeedleRate rate(bath, c.length);
  const NeedleBody body = uniform_rod(c.mass, c.length);
  Engine eng = make_stream(seed, ensemble, Consumer::kNeedle);
  WaitingTimeSolver solver(rate);
  NeedleAverages avg(c, needle_sample_interval(c));
  NeedleEnsemble r;
  std::uint64_t rejected = 0;

  NeedleState s;
  double t = 0.0;
  const std::uint64_t total = c.warmup + c.collisions;
  for (std::uint64_t i = 0; i < total; ++i) {
    if (i == c.warmup) {
      avg.start(t);
      rejected = 0;
    }
    const double wait = c.waiting_time == NeedleWaitingTime::kThinning
                            ? waiting_time_by_thinning(rate, s, eng, &rejected)
                            : sample_by_inversion(solver, s, eng, c);
    t += wait;
    if (i >= c.warmup) avg.advance(t, s);
    // The free rotation up to the collision (eq. 20); v1 and omega are unchanged.
    s.theta = std::remainder(s.theta + s.omega * wait, kTwoPi);
    const double vn = normal_velocity(s);
    Fluxes f;
    const double x = sample_impact_point(rate, vn, s.omega, eng, &f);  // eq. 25
    const double w = vn + s.omega * x;
    const Side side = uniform01(eng) * f.total() < f.plus ? Side::kPlus : Side::kMinus;  // eq. 26
    const double v = bath.sample_colliding(eng, w, side);  // g_+-(v, v_n + x omega)
    apply_needle_impulse(s, body, x, needle_impulse(body, c.alpha, x, w, v));  // eqs. 27-29
    if (slot && (i + 1) % kProgressEvery == 0)
      slot->store(static_cast<double>(i + 1) / static_cast<double>(total));
  }
  avg.finish(t, body, bath.temperature(), &r);
  r.collisions = c.collisions;
  r.fictitious = rejected;
  r.draws = eng.draws();
  return r;
}

}  // namespace granboltz::tv06
