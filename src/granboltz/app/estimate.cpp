#include "granboltz/app/estimate.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <functional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include "granboltz/exec/ensemble_pool.hpp"
#include "granboltz/app/run.hpp"
#include "granboltz/dsmc/observables.hpp"
#include "granboltz/dsmc/run.hpp"
#include "granboltz/dsmc/weighted.hpp"
#include "granboltz/random/rng.hpp"
#include "granboltz/random/samplers.hpp"
#include "granboltz/tv06/bath.hpp"
#include "granboltz/tv06/intruder.hpp"
#include "granboltz/tv06/needle.hpp"

namespace granboltz {

namespace {

// Nanoseconds per event (candidate) on one thread: `make bench`, median of 5, README
// "Performance" table (2 cores of an AMD EPYC at 2.6 GHz; the later Intel Xeon is 1.0-1.3 times
// slower per event, so estimates there are optimistic by up to a quarter). DSMC, global majorant:
// 37.5 ns at n = 4096 and 65536, 49.6 at n = 10^7 (cache misses); pairwise: 38.8, 43.5, 93 at
// n = 10^4, 10^5, 10^6 (58.9, 67.7, 176 before its index streams, scaled by the new/old ratio
// measured side by side on a later machine: 0.66, 0.64, 0.53). TV06: intruder Gillespie 117 per collision, intruder DSMC 19.9 per
// candidate, needle (thinning) 705 per candidate. Two threads run 1.98 times as fast as one.
constexpr double kNsIntruderGillespie = 117.0, kNsIntruderDsmc = 19.9, kNsNeedle = 705.0;
constexpr double kParallelEfficiency = 0.99;
// The work that is not events, timed with `granboltz run -q --threads 1` (user time, Release, on
// the Xeon; gamma = 1e-12 so that no collision happens, one ensemble, differences of two runs):
// a splitting step costs 11 ns (Euler) or 25 ns (Strang: two collision phases) besides its kicks
// (n = 2, 2*10^7 steps); a kick of the splitting schemes, with the majorant's update that follows
// it, 11.5 ns (n = 65536, 2000 steps, the same for lambda 0 and 1 and either majorant; 12.3 at
// n = 10^6). Per particle and observation (n = 65536, 2000 observations): measuring 7.9 ns,
// kicking it up to the observation (no splitting, beta > 0) 6.4 ns, the Gaussian thermostat's fold
// 5.2 ns.
constexpr double kNsEulerStep = 11.0, kNsStrangStep = 25.0, kNsStepKick = 11.5;
constexpr double kNsPerParticleObserved = 7.9, kNsObservationKick = 6.4, kNsGaussianFold = 5.2;
// Binning a particle into a histogram: about 5 ns per particle and observation, for the radial
// histogram about the bulk or the origin alike and again for the component one (n = 65536, 1000
// observations, 100 shells; medians of 3 by CPU time: 1.01 s without, 1.57 origin, 1.68 bulk,
// 2.43 bulk with component).
constexpr double kNsHistogramParticle = 5.0;
// Each observation row costs the output its sums, whatever n (n = 2, 10^4-10^5 rows, moments 0,
// 4 and 16, histograms of 1000 shells): 5.5 us per moment sum of a row (kNumScalars + P of them)
// and 0.24 us per histogram shell, once per run; 0.27 us per moment sum and ensemble, added under
// the record's lock. Neither runs in parallel: they are added to the wall time as they are.
constexpr double kNsRowSum = 5500.0, kNsRowShell = 240.0, kNsEnsembleRowSum = 270.0;
// TV06 samples are counted per event in O(1), but the sample clock's count is a 64-bit integer:
// beyond 2^63 samples its arithmetic overflows and the run never ends (measured: 2000 intruder
// collisions take 0.15 s at sample_every = 1e-15 and do not end in 60 s at 1e-16).
constexpr double kMaxSamples = 0x1p63;
// The estimate integrates the temperature ODE with steps whose number grows like log(t_end), so
// a few hundred in practice; this cap is never reached by a valid config (the rest would be
// added at the rates of the last step).
constexpr int kMaxSteps = 20000;

double interpolate_log(double n, const double (*table)[2], int rows) {
  const double x = std::log10(std::max(n, 1.0));
  if (x <= table[0][0]) return table[0][1];
  for (int k = 1; k < rows; ++k)
    if (x <= table[k][0])
      return table[k - 1][1] + (table[k][1] - table[k - 1][1]) * (x - table[k - 1][0]) /
                                   (table[k][0] - table[k - 1][0]);
  return table[rows - 1][1];
}

double ns_per_dsmc_event(double n, MajorantKind m) {
  static const double global[][2] = {{5.0, 37.5}, {7.0, 49.6}};
  static const double pairwise[][2] = {{4.0, 38.8}, {5.0, 43.5}, {6.0, 93.0}};
  return m == MajorantKind::kPairwise ? interpolate_log(n, pairwise, 3)
                                      : interpolate_log(n, global, 2);
}

// E|u|^p for u Gaussian in d dimensions with variance s2 per component:
// (2 s2)^(p/2) G((d+p)/2) / G(d/2).
double gaussian_moment(double s2, double p, int d = 3) {
  if (d == 2) return std::pow(2.0 * s2, 0.5 * p) * std::tgamma(0.5 * (2.0 + p));
  return std::pow(2.0 * s2, 0.5 * p) * std::tgamma(0.5 * (3.0 + p)) / std::tgamma(1.5);
}

// ln P(|x| > r) for x a 3-D standard Gaussian (chi with 3 degrees of freedom):
// erfc(r/sqrt2) + sqrt(2/pi) r e^(-r^2/2), in logarithms beyond r = 30 where erfc underflows.
double chi3_log_tail(double r) {
  const double c = std::sqrt(2.0 / M_PI);
  if (r < 30.0) return std::log(std::erfc(r / M_SQRT2) + c * r * std::exp(-0.5 * r * r));
  return std::log(c) + std::log(r + 1.0 / r - 1.0 / (r * r * r)) - 0.5 * r * r;
}

// Expected maximum of N independent |x|, x a 3-D standard Gaussian: the 1 - 1/N quantile (by
// bisection, exact for any finite N) plus the Gumbel correction (Euler's constant / (N pdf)).
double chi3_expected_max(double N) {
  if (N < 2) return std::sqrt(8.0 / M_PI);
  if (!std::isfinite(N)) return HUGE_VAL;
  const double target = -std::log(N);
  double lo = 0.0, hi = 64.0;  // ln P(|x| > 64) = -2043 < -ln(DBL_MAX)
  for (int k = 0; k < 64; ++k) {
    const double mid = 0.5 * (lo + hi);
    (chi3_log_tail(mid) > target ? lo : hi) = mid;
  }
  const double x = 0.5 * (lo + hi);
  // N pdf(x) = pdf(x) / P(|x| > x) at the quantile.
  const double log_pdf = 0.5 * std::log(2.0 / M_PI) + 2.0 * std::log(x) - 0.5 * x * x;
  return x + 0.5772156649 / std::exp(log_pdf - chi3_log_tail(x));
}

// The same for a 2-D standard Gaussian: P(|x| > r) = e^(-r^2/2), so the 1 - 1/N quantile is
// sqrt(2 ln N) and N pdf = r there.
double chi2_expected_max(double N) {
  if (N < 2) return std::sqrt(M_PI / 2.0);
  if (!std::isfinite(N)) return HUGE_VAL;
  const double x = std::sqrt(2.0 * std::log(N));
  return x + 0.5772156649 / x;
}

double chi_expected_max(double N, int d) {
  return d == 2 ? chi2_expected_max(N) : chi3_expected_max(N);
}

// The share of a Maxwellian's collisional energy loss that inelasticity keeps, as it enters the
// moment equation: <|u|^lambda g_n^2 (1 - eps(g_n)^2)> / <|u|^lambda g_n^2> over relative
// velocities at temperature T (u = sqrt(T) r, r with density r^2 e^(-r^2/4)) and impact normals
// (g_n^2 = |u|^2 z, z = (1 - u.e/|u|)/2 uniform on [0, 1]). It is 1 - alpha^2 for constant alpha;
// for a law of g_n it depends on T (the Maxwellian approximation, as for constant alpha). In
// d = 2 the same 3-D average stands in (an estimate).
// Midpoint sums: 64 x 32 points, below 1e-4 relative for the viscoelastic law.
double inelastic_fraction(const RestitutionLaw& law, double lambda, double T) {
  constexpr int kR = 64, kZ = 32;
  constexpr double kRMax = 14.0;  // e^(-49) of the weight is left out
  double loss = 0.0, norm = 0.0;
  for (int i = 0; i < kR; ++i) {
    const double r = (i + 0.5) * kRMax / kR;
    const double wr = std::pow(r, 4.0 + lambda) * std::exp(-0.25 * r * r);
    for (int k = 0; k < kZ; ++k) {
      const double z = (k + 0.5) / kZ;
      const double eps =
          std::visit([&](const auto& l) { return l.eps_of_g2(T * r * r * z); }, law);
      loss += wr * z * (1.0 - eps * eps);
      norm += wr * z;
    }
  }
  return loss / norm;
}

struct DsmcEvents {
  double collisions = 0, candidates = 0, kicks = 0;
  double ns = 0;         // one ensemble on one thread: events, steps, observations
  double serial_ns = 0;  // the run's output sums (all ensembles, not in parallel)
};

// One ensemble of a DSMC config (constant weights): the events, and their time on one thread.
DsmcEvents dsmc_events(const DsmcConfig& d, double ensembles) {
  const double n = static_cast<double>(d.particles);
  const double lambda = d.kernel.lambda, gc = d.kernel.gamma * d.kernel.C;
  const bool heated = d.thermostat == Thermostat::kWhiteNoise && d.beta > 0.0;
  const bool gaussian = d.thermostat == Thermostat::kGaussian;
  const bool split = d.scheme != Scheme::kNoSplit;
  const bool pairwise = d.majorant == MajorantKind::kPairwise;
  const double observations = static_cast<double>(d.observations());
  const double steps = split ? static_cast<double>(d.steps) : 0.0;
  // dT/dt = heat - B T^(1 + lambda/2): white noise heats by 2 beta, collisions cool (the moment
  // equation of a Maxwellian); the Gaussian thermostat holds T at T0, so both are 0 there.
  // In d dimensions B = area/(8d) <1 - u^.e> gamma C (1 - alpha^2) (n-1)/n E|u|^(2+lambda): pi/6
  // in d = 3; pi/8 times <1 - u^.e> = 1 (uniform) or 4/3 (hard-disk impacts) in d = 2.
  const int dim = d.dimension;
  const double loss_geometry =
      dim == 2 ? (d.geometry == Geometry::kImpact ? 4.0 / 3.0 : 1.0) / 8.0 : 1.0 / 6.0;
  const double heat = heated ? 2.0 * d.beta : 0.0;
  const double B = gaussian ? 0.0
                   : dim == 2 ? M_PI * loss_geometry * gc * (1.0 - d.alpha * d.alpha) * (n - 1.0) / n *
                                    gaussian_moment(2.0, 2.0 + lambda, 2)
                            : M_PI * gc * (1.0 - d.alpha * d.alpha) * (n - 1.0) / (6.0 * n) *
                                  gaussian_moment(2.0, 2.0 + lambda);
  // A law of g_n (viscoelastic): the same equation with 1 - alpha^2 replaced by its Maxwellian
  // average at the current T (inelastic_fraction), so the rates follow the law's cooling. The
  // event counts for a given T(t) do not depend on the law.
  const bool constant_law = is_constant(d.restitution);
  const double B1 = gaussian ? 0.0
                    : dim == 2 ? M_PI * loss_geometry * gc * (n - 1.0) / n *
                                     gaussian_moment(2.0, 2.0 + lambda, 2)
                             : M_PI * gc * (n - 1.0) / (6.0 * n) * gaussian_moment(2.0, 2.0 + lambda);
  auto B_at = [&](double T_now) {
    return constant_law || gaussian ? B : B1 * inelastic_fraction(d.restitution, lambda, T_now);
  };
  const double p = 0.5 * lambda;
  // Real collisions at 2 pi gamma C (n-1) E|u|^lambda = A T^(lambda/2); pairwise candidates at
  // 4 pi gamma C (n-1) E|v-V|^lambda = Ap T^(lambda/2); global ones at 2 pi gamma C (n-1) U^lambda
  // (area/2 and area for 2 pi and 4 pi in d dimensions).
  const double area = d.kernel.area;
  const double A = 0.5 * area * gc * (n - 1.0) * gaussian_moment(2.0, lambda, dim);
  const double Ap = area * gc * (n - 1.0) * gaussian_moment(1.0, lambda, dim);
  const double Ag = 0.5 * area * gc * (n - 1.0);
  const double factor = d.majorant_update == MajorantUpdate::kStrict ? 2.0 : 1.0;
  const double T0 = d.initial_temperature;
  const double u0 = 2.0 * std::sqrt(T0) * chi_expected_max(n, dim);  // GRW05 step 1.4
  const bool tracks_max = !pairwise && lambda > 0.0;
  DsmcEvents e;
  double T = T0, t = 0.0, T_peak = T0, u_max = u0;
  auto real_rate = [&](double T_now) { return A * std::pow(T_now, p); };
  auto candidate_rate = [&](double T_now, double u) {
    if (lambda == 0.0) return real_rate(T_now);
    return pairwise ? Ap * std::pow(T_now, p) : Ag * std::pow(u, lambda);
  };
  // The independent velocities U_max has seen by time t: n at the start, and both partners of
  // every collision. The kicks between collisions (of the candidates' partners, of every
  // particle at the splitting steps and observations) are seen too, but they move a velocity by
  // little: counting them as new velocities overestimated the fictitious candidates by 17 %.
  auto seen = [&](double) { return n + 2.0 * e.collisions; };
  auto dT = [&](double T_now) { return heat - B_at(T_now) * std::pow(T_now, 1.0 + p); };
  // The fixed point of the ODE, once it is reached the rates change only with U_max.
  double T_star = heat > 0.0 && B > 0.0 ? std::pow(heat / B, 1.0 / (1.0 + p)) : NAN;
  if (!constant_law && heat > 0.0 && B1 > 0.0) {
    // The cooling B_at(T) T^(1+p) grows with T for a law whose eps falls with g_n: the fixed
    // point by bisection in ln T, once bracketed (none if the law is elastic, delta = 0).
    double lo = std::log(std::pow(heat / B1, 1.0 / (1.0 + p))), hi = lo;
    while (dT(std::exp(lo)) < 0.0 && lo > -700.0) lo -= 8.0;
    while (dT(std::exp(hi)) > 0.0 && hi < 700.0) hi += 8.0;
    if (dT(std::exp(lo)) >= 0.0 && dT(std::exp(hi)) <= 0.0) {
      for (int k = 0; k < 60; ++k) {
        const double mid = 0.5 * (lo + hi);
        (dT(std::exp(mid)) > 0.0 ? lo : hi) = mid;
      }
      T_star = std::exp(0.5 * (lo + hi));
    }
  }
  bool steady = gaussian || lambda == 0.0;  // T plays no role for the rates then
  if (!std::isfinite(A * (constant_law ? B : B1) * heat * T0 * d.t_end * u0 + 1.0)) {  // cannot be integrated
    e.collisions = e.candidates = NAN;
    return e;
  }
  for (int step = 0; t < d.t_end; ++step) {
    double h = d.t_end - t;
    if (step == kMaxSteps) {  // the rest at the last rates (never reached by a valid config)
      e.collisions += h * real_rate(T);
      e.candidates += h * candidate_rate(T, u_max);
      break;
    }
    if (!steady && std::isfinite(T_star) && std::fabs(T - T_star) <= 1e-6 * T_star) {
      steady = true;
      T = T_star;
    }
    if (!steady) {  // RK4 steps that change T by a few per cent and resolve its relaxation
      const double rate = std::fabs(dT(T)), relax = B_at(T) * (1.0 + p) * std::pow(T, p);
      if (rate > 0.0) h = std::min(h, 0.05 * T / rate);
      if (relax > 0.0) h = std::min(h, 0.05 / relax);
    }
    if (tracks_max) {  // U_max grows like sqrt(log(seen)): steps of a growing fraction of t
      const double seen_rate = 2.0 * real_rate(T);
      h = std::min(h, std::max(0.5 * t, 0.1 * n / seen_rate));
    }
    if (!(h > 0.0) || t + h == t) h = d.t_end - t;  // no progress left in double precision
    const double r0 = real_rate(T), c0 = candidate_rate(T, u_max);
    if (!steady) {
      const double k1 = dT(T), k2 = dT(T + 0.5 * h * k1), k3 = dT(T + 0.5 * h * k2),
                   k4 = dT(T + h * k3);
      T = std::max(T + h / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4), 1e-300);
    }
    t += h;
    T_peak = std::max(T_peak, T);
    e.collisions += 0.5 * h * (r0 + real_rate(T));
    // U_max follows the largest |v - V| the update has seen, Maxwellian at the highest
    // temperature reached so far.
    if (tracks_max)
      u_max = std::max(u_max, factor * std::sqrt(T_peak) * chi_expected_max(seen(t), dim));
    e.candidates += 0.5 * h * (c0 + candidate_rate(T, u_max));
    if (!std::isfinite(e.candidates)) break;
  }
  e.candidates = std::max(e.candidates, e.collisions);
  if (heated) {
    if (!split)  // both partners at every candidate, all at observations
      e.kicks = 2.0 * e.candidates + n * observations;
    else
      e.kicks = n * steps;
  }
  const double histograms = d.histogram.shells ? (d.histogram.component ? 2.0 : 1.0) : 0.0;
  e.ns = e.candidates * ns_per_dsmc_event(n, d.majorant) +
         n * (observations + 1.0) * (kNsPerParticleObserved + histograms * kNsHistogramParticle);
  if (split) e.ns += steps * (d.scheme == Scheme::kEuler ? kNsEulerStep : kNsStrangStep);
  if (heated) e.ns += split ? e.kicks * kNsStepKick : n * observations * kNsObservationKick;
  if (gaussian) e.ns += n * (observations + 1.0) * kNsGaussianFold;
  // The component histogram has as many bins as the radial one.
  const double sums = kNumScalars + d.moments,
               shells = d.histogram.shells ? (static_cast<double>(d.histogram.shells) + 1.0) *
                                                 (d.histogram.component ? 2.0 : 1.0)
                                           : 0.0;
  e.serial_ns = (observations + 1.0) * (sums * (kNsRowSum + ensembles * kNsEnsembleRowSum) +
                                        shells * kNsRowShell);
  return e;
}

// SWPM (dsmc.weights: swpm): the particle number, the majorant and the split and reduction
// sweeps follow the weighted dynamics, which no closed form gives, so events and time are
// measured on a pilot, ensemble 0 of the run itself, until it has drawn kPilotCandidates
// candidates; the rates of its second half are extrapolated to t_end. The pilot stops at the
// observations (a run kicks every particle there) and at least kPilotStops times in [0, t_end];
// the kicks of its stops are not counted, those of the run's observations are added.
// It runs in a child process that reports every stop through a pipe and is killed after
// kPilotSeconds: a huge gamma puts 10^5 candidates into a sliver of the first stop, a tiny one
// never draws them, and an extreme config can keep one reduction busy for minutes (gamma = 1e12:
// more than 10 minutes), none of which a flag checked between events could stop. The estimate is
// extrapolated from the last stop reported.
// Thrown inside the estimate when a quantity it cannot represent turns up (not a config error
// by itself: estimate_run names the key).
struct NotFinite {
  std::string why;
};

constexpr double kPilotCandidates = 1e5;
constexpr double kPilotStops = 64.0;
constexpr double kPilotSeconds = 1.0;

struct WeightedCost {
  DsmcEvents events;
  double seconds = 0.0;  // one ensemble on one thread
  bool stuck = false;    // the pilot did not pass its first stop: seconds is a lower bound
};

// One stop of the pilot: its events so far, and what the extrapolation needs besides.
struct PilotMark {
  double t, candidates, collisions, kicks, seconds;
  double observed, observation_kicks, particles;
};

// Runs the pilot, handing every stop to `emit`.
template <class Emit>
void run_pilot(const DsmcConfig& d, std::uint64_t seed, Emit&& emit) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  WeightedEnsemble pilot(d, seed, 0);
  const bool heated = d.thermostat == Thermostat::kWhiteNoise && d.beta > 0.0;
  const std::vector<double> times = dsmc_times(d);
  double stop_kicks = 0.0, observation_kicks = 0.0, observed = 0.0, candidates = 0.0;
  auto mark = [&](double t) {
    const EventCounts& c = pilot.counts();
    candidates = static_cast<double>(c.collisions + c.fictitious);
    emit(PilotMark{t, candidates, static_cast<double>(c.collisions),
                   static_cast<double>(c.kicks) - stop_kicks,
                   std::chrono::duration<double>(Clock::now() - start).count(), observed,
                   observation_kicks, static_cast<double>(pilot.particles().size())});
  };
  mark(0.0);
  for (std::size_t m = 1; m < times.size() && candidates < kPilotCandidates; ++m) {
    const double from = times[m - 1], to = times[m];
    const double pieces = std::max(1.0, std::ceil((to - from) * kPilotStops / d.t_end));
    for (double k = 1.0; k <= pieces && candidates < kPilotCandidates; ++k) {
      const double s = k == pieces ? to : from + (to - from) * k / pieces;
      pilot.advance_to(s);
      const double n = static_cast<double>(pilot.particles().size());
      if (heated) stop_kicks += n;  // kick_all_to(s) at the end of advance_to
      if (k == pieces) {  // an observation of the run
        ++observed;
        if (heated) observation_kicks += n;
      }
      mark(s);
    }
  }
}

// The pilot's stops, from a child process given kPilotSeconds (in this process if it cannot
// fork). An error of the pilot (the run would meet it too) is thrown here with its message.
std::vector<PilotMark> pilot_marks(const DsmcConfig& d, std::uint64_t seed) {
  std::vector<PilotMark> marks;
  int fds[2];
  if (::pipe(fds) != 0) {
    run_pilot(d, seed, [&](const PilotMark& m) { marks.push_back(m); });
    return marks;
  }
  const pid_t child = ::fork();
  if (child < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    run_pilot(d, seed, [&](const PilotMark& m) { marks.push_back(m); });
    return marks;
  }
  if (child == 0) {  // the pilot; a record with t < 0 carries an error message
    ::close(fds[0]);
    auto put = [&](const void* p, std::size_t bytes) {
      const char* c = static_cast<const char*>(p);
      while (bytes) {
        const ssize_t w = ::write(fds[1], c, bytes);
        if (w <= 0) ::_exit(1);
        c += w, bytes -= static_cast<std::size_t>(w);
      }
    };
    try {
      run_pilot(d, seed, [&](const PilotMark& m) { put(&m, sizeof m); });
    } catch (const std::exception& x) {
      const std::string what = x.what();
      PilotMark error{-1.0, static_cast<double>(what.size()), 0, 0, 0, 0, 0, 0};
      put(&error, sizeof error);
      put(what.data(), what.size());
    }
    ::_exit(0);
  }
  ::close(fds[1]);
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + std::chrono::duration<double>(kPilotSeconds);
  std::string buffer, error;
  bool failed = false;
  for (;;) {
    const double left = std::chrono::duration<double>(deadline - Clock::now()).count();
    if (left <= 0) break;
    pollfd p{fds[0], POLLIN, 0};
    const int ready = ::poll(&p, 1, static_cast<int>(std::ceil(left * 1000)));
    if (ready < 0 && errno == EINTR) continue;
    if (ready <= 0) break;
    char chunk[4096];
    const ssize_t r = ::read(fds[0], chunk, sizeof chunk);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) break;  // the pilot is done
    buffer.append(chunk, static_cast<std::size_t>(r));
  }
  ::kill(child, SIGKILL);  // ours, by its id; a no-op if it has ended
  ::waitpid(child, nullptr, 0);
  ::close(fds[0]);
  for (std::size_t at = 0; at + sizeof(PilotMark) <= buffer.size(); at += sizeof(PilotMark)) {
    PilotMark m;
    std::memcpy(&m, buffer.data() + at, sizeof m);
    if (m.t < 0) {
      failed = true;
      error = buffer.substr(at + sizeof m, static_cast<std::size_t>(m.candidates));
      break;
    }
    marks.push_back(m);
  }
  if (failed) throw std::runtime_error(error);
  return marks;
}

WeightedCost weighted_cost(const DsmcConfig& d, std::uint64_t seed) {
  const bool heated = d.thermostat == Thermostat::kWhiteNoise && d.beta > 0.0;
  const std::vector<PilotMark> marks = pilot_marks(d, seed);
  WeightedCost cost;
  // A pilot that did not pass its first stop (1/64 of t_end at most) in kPilotSeconds: the run
  // takes longer than kPilotStops times that, all that is known.
  WeightedCost stuck;
  stuck.stuck = true;
  stuck.seconds = kPilotSeconds * kPilotStops;
  if (marks.size() < 2) return stuck;
  const PilotMark& last = marks.back();
  // The rates of the pilot's second half (the particle number has left its initial value).
  const PilotMark* half = &marks.front();
  for (const PilotMark& x : marks)
    if (x.t >= 0.5 * last.t && x.t < last.t) {
      half = &x;
      break;
    }
  const double ahead = d.t_end - last.t, span = last.t - half->t;
  if (!(span > 0.0)) return stuck;
  auto extrapolate = [&](double PilotMark::*x) {
    if (!(ahead > 0.0)) return last.*x;
    return last.*x + (last.*x - half->*x) / span * ahead;
  };
  cost.events.candidates = extrapolate(&PilotMark::candidates);
  cost.events.collisions = extrapolate(&PilotMark::collisions);
  const double remaining = static_cast<double>(d.observations()) - last.observed;
  cost.events.kicks = extrapolate(&PilotMark::kicks) + last.observation_kicks +
                      (heated ? remaining * last.particles : 0.0);
  // The pilot's wall time so far is in its last stop; the time to its kill is not.
  cost.seconds = extrapolate(&PilotMark::seconds);
  return cost;
}

// A pilot ensemble of a needle, at most 20 000 collisions (~15 ms): the thinning's rejected
// candidates per collision (Phi(|v1|, omega) against Phi(v_n, omega) along the free rotations),
// and the simulated time per collision. Both depend on the stationary state of (v1, omega),
// which no closed form gives for an inelastic needle (equipartition overestimates them by
// 14-50 %). The pilot uses the thinning whatever the config's method (the same law) and the
// default sampling (its own samples are not used).
struct NeedlePilot {
  double fictitious_per_collision = 0.0, time_per_collision = 0.0;
};

NeedlePilot needle_pilot(const NeedleConfig& c) {
  NeedleConfig pilot = c;
  pilot.collisions = std::min<std::uint64_t>(c.collisions, 20000);
  pilot.warmup = std::min<std::uint64_t>(c.warmup, 2000);
  pilot.velocity_histogram.bins = pilot.omega_histogram.bins = 0;
  pilot.waiting_time = NeedleWaitingTime::kThinning;
  pilot.sample_every = 0.0;
  NeedlePilot r;
  try {
    const tv06::NeedleEnsemble e = tv06::simulate_needle(pilot, 0, 0);
    const double collisions = static_cast<double>(e.collisions);
    if (c.waiting_time == NeedleWaitingTime::kThinning)
      r.fictitious_per_collision = static_cast<double>(e.fictitious) / collisions;
    r.time_per_collision = e.time / collisions;
  } catch (const std::exception&) {
    // A pilot too short to sample: the run is short too; its time from the rate at rest.
    r.time_per_collision = tv06::needle_sample_interval(pilot);
  }
  return r;
}

// <phi(v1)>, the mean collision rate of the intruder, v1 ~ N(0, s1^2) at the intruder's
// temperature (81-point rule).
template <class Bath>
double intruder_mean_rate(const Bath& bath, double s1) {
  double phi = 0.0;
  for (int k = -40; k <= 40; ++k) {
    const double x = 0.15 * k;
    phi += 0.15 * std::exp(-0.5 * x * x) / std::sqrt(2 * M_PI) * bath.fluxes(x * s1).total();
  }
  return phi;
}

struct IntruderCost {
  double candidates = 0.0;  // DSMC method; the collisions otherwise
  double mean_rate = 0.0;   // <phi(v1)>
};

// Candidates of the DSMC intruder (TV06 §4): omega_max = 2 rho max|v_i - v1| (the 1 - 1/N quantile
// of |v - v1|) over the bath velocities drawn so far (n, plus one per candidate with the `tested`
// refresh) against the mean collision rate <phi(v1)>, v1 Maxwellian at the intruder's temperature.
// The quantile changes like log(N): with the `tested` refresh the collisions are taken in
// geometric blocks, so its cost (a table of the tail, then one bisection per block) is bounded.
IntruderCost intruder_cost(const IntruderConfig& c, double collisions) {
  double ratio = 1.0;
  tv06::intruder_exact_temperature_ratio(c, &ratio);
  const double T_B = tv06::intruder_bath_temperature(c);
  const double s1 = std::sqrt(ratio * T_B / c.mass);  // sd of v1
  auto body = [&](auto bath) {
    IntruderCost r;
    const double phi = intruder_mean_rate(bath, s1);
    r.mean_rate = phi;
    if (c.method != IntruderMethod::kDsmc) {
      r.candidates = collisions;
      return r;
    }
    // The 1 - 1/N quantile of |v| from a table of the tail P(|v| > x) (trapezoidal rule on the
    // pdf), then the records as N grows.
    std::vector<std::pair<double, double>> tail;  // (x, P(|v| > x))
    const double scale = std::sqrt(T_B);
    double p = 0.0, prev = bath.pdf(1e6 * scale);
    for (double x = 1e6 * scale; x > 0.0; x *= 0.999) {
      const double f = bath.pdf(x);
      p += 2.0 * 0.5 * (f + prev) * (x / 0.999 - x);
      prev = f;
      tail.emplace_back(x, p);
      if (x < 1e-3 * scale) break;
    }
    auto T = [&](double y) {  // P(|v| > y), y >= 0: the first entry at or below y (x decreases)
      const auto it = std::lower_bound(tail.begin(), tail.end(), y,
                                       [](const auto& e, double v) { return e.first > v; });
      return it == tail.end() ? 1.0 : it->second;
    };
    auto above = [&](double y) { return y >= 0 ? 0.5 * T(y) : 1.0 - 0.5 * T(-y); };  // P(v > y)
    // P(|v - v1| > x) for v1 ~ N(0, s1^2), then its 1 - 1/N quantile by bisection.
    auto diff_tail = [&](double x) {
      double sum = 0.0;
      for (int k = -24; k <= 24; ++k) {
        const double z = 0.25 * k, w = 0.25 * std::exp(-0.5 * z * z) / std::sqrt(2 * M_PI);
        sum += w * (above(x + z * s1) + above(x - z * s1));
      }
      return sum;
    };
    auto quantile = [&](double N) {
      double lo = 0.0, hi = tail.front().first;
      for (int k = 0; k < 60; ++k) {
        const double mid = 0.5 * (lo + hi);
        (diff_tail(mid) * N > 1.0 ? lo : hi) = mid;
      }
      return lo;
    };
    const double n = static_cast<double>(c.bath_particles);
    if (c.bath_refresh != BathRefresh::kTested) {
      r.candidates = collisions * 2.0 * c.density * quantile(n) / phi;
      return r;
    }
    // Blocks of at most collisions/400, and at most a tenth of the candidates so far: 400 blocks
    // at most, fewer for few collisions.
    double done = 0.0, candidates = 0.0;
    const double step = std::max(1.0, collisions / 400.0);
    for (int k = 0; done < collisions && k < 1000; ++k) {
      const double h = std::min({step, collisions - done, std::max(1.0, 0.1 * (n + candidates))});
      const double omega_max = 2.0 * c.density * quantile(n + candidates);
      candidates += h * omega_max / phi;
      done += h;
    }
    if (done < collisions)  // never with the bounds above; the rest at the last majorant
      candidates += (collisions - done) * 2.0 * c.density * quantile(n + candidates) / phi;
    r.candidates = candidates;
    return r;
  };
  return c.bath.kind == BathKind::kGaussian ? body(tv06::gaussian_bath(c.bath.a, c.density))
                                            : body(tv06::power_law_bath(c.bath.a, c.density));
}

std::string human_seconds(double s) {
  char buf[48];
  if (s < 120)
    std::snprintf(buf, sizeof buf, "%.2g s", s);
  else if (s < 7200)
    std::snprintf(buf, sizeof buf, "%.1f min", s / 60);
  else if (s < 3 * 86400)
    std::snprintf(buf, sizeof buf, "%.1f h", s / 3600);
  else if (s < 1e6 * 86400)
    std::snprintf(buf, sizeof buf, "%.1f days", s / 86400);
  else
    std::snprintf(buf, sizeof buf, "%.2g days", s / 86400);
  return buf;
}

std::string format_samples(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}

bool finite(const RunEstimate& e) {
  return std::isfinite(e.collisions) && std::isfinite(e.fictitious) && std::isfinite(e.kicks) &&
         std::isfinite(e.seconds) && e.collisions >= 0 && e.fictitious >= 0 && e.kicks >= 0 &&
         e.seconds >= 0;
}

RunEstimate estimate_unchecked(const Config& config, unsigned threads, bool pilots) {
  RunEstimate e;
  e.ensembles = config.last_ensemble() - config.first_ensemble();
  e.threads = resolve_threads(threads, e.ensembles);
  e.memory_bytes = estimate_memory(config, e.threads);
  const double N = static_cast<double>(e.ensembles);
  double ns = 0.0, serial_ns = 0.0;  // one thread, all ensembles; and not parallel at all
  if (config.model == Model::kDsmc) {
    const DsmcConfig& d = config.dsmc;
    DsmcEvents one = dsmc_events(d, N);
    serial_ns = one.serial_ns;
    if (d.weights.swpm && pilots) {
      // The constant-weight events first: a config whose cost is not finite gets no pilot.
      e.collisions = one.collisions, e.fictitious = one.candidates, e.kicks = one.kicks;
      e.seconds = one.ns;
      if (!finite(e)) return e;
      const WeightedCost pilot = weighted_cost(d, config.seed);
      const double observe_ns = one.ns - one.candidates * ns_per_dsmc_event(
                                                              static_cast<double>(d.particles),
                                                              d.majorant);
      // A stuck pilot: the events of constant weights stand in, and the time is a lower bound,
      // the larger of the pilot's and that of the constant-weight events.
      e.lower_bound = pilot.stuck;
      ns = N * (pilot.stuck ? std::max(pilot.seconds * 1e9, one.ns)
                            : pilot.seconds * 1e9 + std::max(0.0, observe_ns));
      if (!pilot.stuck) one = pilot.events;
    } else {
      ns = N * one.ns;
    }
    e.collisions = N * one.collisions;
    e.fictitious = N * (one.candidates - one.collisions);
    e.kicks = N * one.kicks;
  } else if (config.model == Model::kIntruder) {
    const IntruderConfig& c = config.intruder;
    const double per = static_cast<double>(c.warmup + c.collisions);
    e.collisions = N * per;
    const IntruderCost cost = intruder_cost(c, per);
    if (c.method == IntruderMethod::kDsmc) {
      e.fictitious = N * std::max(0.0, cost.candidates - per);
      ns = N * cost.candidates * kNsIntruderDsmc;
    } else {
      ns = e.collisions * kNsIntruderGillespie;
    }
    const double samples =
        static_cast<double>(c.collisions) / cost.mean_rate / tv06::intruder_sample_interval(c);
    if (!(samples < kMaxSamples))
      throw NotFinite{"the run would take " + format_samples(samples) +
                      " samples per ensemble, more than its 64-bit sample clock counts (2^63)"};
  } else {
    const NeedleConfig& c = config.needle;
    e.collisions = N * static_cast<double>(c.warmup + c.collisions);
    // Without the pilot, the time per collision of a needle at rest.
    NeedleConfig rest = c;
    rest.sample_every = 0.0;
    const NeedlePilot pilot =
        pilots ? needle_pilot(c) : NeedlePilot{0.0, tv06::needle_sample_interval(rest)};
    e.fictitious = e.collisions * pilot.fictitious_per_collision;
    ns = (e.collisions + e.fictitious) * kNsNeedle;
    const double samples = static_cast<double>(c.collisions) * pilot.time_per_collision /
                           tv06::needle_sample_interval(c);
    if (!(samples < kMaxSamples))
      throw NotFinite{"the run would take " + format_samples(samples) +
                      " samples per ensemble, more than its 64-bit sample clock counts (2^63)"};
  }
  const double workers = std::min<double>(e.threads, std::max(N, 1.0));
  e.seconds = ns * 1e-9 / (workers > 1 ? workers * kParallelEfficiency : 1.0) + serial_ns * 1e-9;
  return e;
}

// The config keys whose extreme values can make the cost of a run unrepresentable, each with a
// tame value to try in its place.
struct Suspect {
  std::string key;
  double value;
  std::function<void(Config&)> tame;
};

std::vector<Suspect> suspects(const Config& config) {
  std::vector<Suspect> s;
  if (config.model == Model::kDsmc) {
    const DsmcConfig& d = config.dsmc;
    s.push_back({"dsmc.beta", d.beta, [](Config& c) { c.dsmc.beta = c.dsmc.beta > 0 ? 1.0 : 0.0; }});
    s.push_back({"dsmc.gamma", d.kernel.gamma, [](Config& c) { c.dsmc.kernel.gamma = 1.0; }});
    s.push_back({"dsmc.kernel.C", d.kernel.C, [](Config& c) { c.dsmc.kernel.C = 0.1; }});
    s.push_back({"dsmc.initial.temperature", d.initial_temperature,
                 [](Config& c) { c.dsmc.initial_temperature = 1.0; }});
    s.push_back({"dsmc.t_end", d.t_end, [](Config& c) {
                   c.dsmc.observe_every /= c.dsmc.t_end;
                   c.dsmc.t_end = 1.0;
                 }});
    s.push_back({"dsmc.particles", static_cast<double>(d.particles),
                 [](Config& c) { c.dsmc.particles = 1000; }});
    if (d.scheme != Scheme::kNoSplit)
      s.push_back({"dsmc.steps", static_cast<double>(d.steps), [](Config& c) {
                     c.dsmc.steps = std::max<std::uint64_t>(1, c.dsmc.observations());
                   }});
  } else if (config.model == Model::kIntruder) {
    const IntruderConfig& c = config.intruder;
    s.push_back({"intruder.sample_every", c.sample_every,
                 [](Config& x) { x.intruder.sample_every = 0.0; }});
    s.push_back({"intruder.bath.a", c.bath.a, [](Config& x) { x.intruder.bath.a = 1.0; }});
    s.push_back({"intruder.density", c.density, [](Config& x) { x.intruder.density = 1.0; }});
    s.push_back({"intruder.mass", c.mass, [](Config& x) { x.intruder.mass = 1.0; }});
  } else {
    const NeedleConfig& c = config.needle;
    s.push_back({"needle.sample_every", c.sample_every,
                 [](Config& x) { x.needle.sample_every = 0.0; }});
    s.push_back({"needle.length", c.length, [](Config& x) { x.needle.length = 1.0; }});
    s.push_back({"needle.a", c.a, [](Config& x) { x.needle.a = 1.0; }});
    s.push_back({"needle.density", c.density, [](Config& x) { x.needle.density = 1.0; }});
    s.push_back({"needle.mass", c.mass, [](Config& x) { x.needle.mass = 1.0; }});
  }
  s.push_back({"ensembles", static_cast<double>(config.ensembles), [](Config& c) {
                 c.ensembles = 1;
                 c.shard = Shard{};
               }});
  // The most extreme first: the key whose tame value alone makes the estimate finite is named.
  std::stable_sort(s.begin(), s.end(), [](const Suspect& a, const Suspect& b) {
    auto extreme = [](double v) { return v > 0 ? std::fabs(std::log(v)) : 0.0; };
    return extreme(a.value) > extreme(b.value);
  });
  return s;
}

std::string cut(std::string s) {
  if (s.size() > 80) s = s.substr(0, 77) + "...";
  return s;
}

}  // namespace

RunEstimate estimate_run(const Config& config, unsigned threads) {
  std::string why = "overflow";
  try {
    const RunEstimate e = estimate_unchecked(config, threads, true);
    if (finite(e)) return e;
  } catch (const NotFinite& x) {
    why = x.why;
  }
  auto closed_form_finite = [&](const Config& c) {
    try {
      return finite(estimate_unchecked(c, threads, false));
    } catch (const NotFinite&) {
      return false;
    }
  };
  // Only a pilot (SWPM) failed: no single key is to blame.
  if (closed_form_finite(config))
    throw ConfigError("the run's cost cannot be estimated: " + why);
  // Which key: the first (most extreme) whose tame value alone gives a finite estimate, without
  // the pilots (SWPM, needle) that the search would otherwise repeat.
  for (const Suspect& s : suspects(config)) {
    Config tamed = config;
    s.tame(tamed);
    if (closed_form_finite(tamed))
      throw ConfigError(cut(s.key + " = " + format_real(s.value)) + ": " +
                        (why == "overflow" ? "the run's cost cannot be estimated (overflow)"
                                           : why) +
                        "; choose a less extreme value");
  }
  throw ConfigError("the run's cost estimate is not finite (" + why +
                    "); check the config's extreme values");
}

std::string describe(const RunEstimate& e) {
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "%llu ensembles: %.3g collisions, %.3g fictitious, %.3g kicks; peak memory %s; "
                "wall time %s %s on %u thread%s",
                static_cast<unsigned long long>(e.ensembles), e.collisions, e.fictitious, e.kicks,
                human_bytes(static_cast<double>(e.memory_bytes)).c_str(),
                e.lower_bound ? "more than" : "about", human_seconds(e.seconds).c_str(), e.threads, e.threads == 1 ? "" : "s");
  return buf;
}

std::string human_bytes(double b) {
  const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB"};
  int u = 0;
  while (b >= 1024 && u < 5) {
    b /= 1024;
    ++u;
  }
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f %s", b, units[u]);
  return buf;
}

}  // namespace granboltz
