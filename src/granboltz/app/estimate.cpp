#include "granboltz/app/estimate.hpp"

#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <new>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <variant>
#include <vector>

#include "granboltz/app/output.hpp"
#include "granboltz/app/run.hpp"
#include "granboltz/dsmc/engine.hpp"
#include "granboltz/dsmc/observables.hpp"
#include "granboltz/dsmc/run.hpp"
#include "granboltz/exec/ensemble_pool.hpp"
#include "granboltz/physics/pair_collision.hpp"
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
// measured side by side on a later machine: 0.66, 0.64, 0.53). TV06: intruder Gillespie 117 per
// collision, intruder DSMC 19.9 per candidate, needle (thinning) 705 per candidate. Two threads
// run 1.98 times as fast as one.
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
// The output's sums and counts (all of them: the record's layout, built without allocating),
// timed with `granboltz run -q --threads 1` (n = 2, 10^4-10^5 rows, moments 0, 4 and 16,
// histograms of 1000 shells): 5.5 us per moment sum (Moments2: two exact sums, allocated, turned
// into mean and interval, written) and 0.24 us per histogram count, once per run; 0.27 us per
// moment sum and ensemble, added under the record's lock. Measured later on a shared EPYC by CPU
// time (median of 3, n = 2, one thread) and scaled to the machine of the constants above by the
// ratio of the same runs' row sums and counts there (10 us and 380 ns: 1.7): a count costs
// 3.2 ns per ensemble (added under the lock), a moment sum 60 ns per ensemble (not 270: rows of
// 20 and 36 sums, 1 and 16 ensembles), the steady histogram's sums 5.2 us each as the others
// (n = 2, 10^5 shells, 11 and 101 rows, 1 and 16 ensembles: 0.44-6.1 s), SWPM's weight per row
// and shell 6 us; and with steady_from each ensemble averages its steady rows at 2.3 ns per row
// and shell. A 10^6-shell steady histogram was estimated 4-13 times too low before these, and
// SWPM's weights per shell not at all. None of this runs in parallel: it is added to the wall
// time as it is. The process itself (start, HDF5, the output's attributes) takes 14 ms.
constexpr double kNsMomentSum = 5500.0, kNsCount = 240.0, kNsEnsembleMomentSum = 60.0,
                 kNsEnsembleCount = 3.2, kNsSteadyRowShellEnsemble = 2.3;
constexpr double kFixedSeconds = 0.014;
// An event of the global majorant is not one cost: a fictitious candidate (waiting time, pair,
// acceptance) is cheaper than a real collision, and the kicks of both partners (no splitting,
// beta > 0) cost besides. Split that way, from runs of n = 4096 on one thread (CPU time, median
// of 3, on the shared EPYC, divided by 1.75 so that the RW05 Maxwell config gives its 37.5 ns):
// 14.6 ns per candidate, 7.3 more per real collision, 7.8 per kick (11.4 for lambda > 0, whose
// kick updates the majorant); this gives 37.5 (RW05 Maxwell), 38.3 (GRW05 Ex. 5: 38.2) and 16.3
// (the elastic peer config: 17.3) of the table, and free cooling and the Gaussian thermostat,
// which have no kicks, are no longer costed as heated runs (1.3-1.7 times too high). Larger n
// cost more per event (cache misses) in the same proportion as ns_per_dsmc_event.
constexpr double kNsCandidate = 14.6, kNsCollision = 7.3, kNsKickMaxwell = 7.8, kNsKick = 11.4;
// A kick of drag, or of shear with noise (the exact propagator: an exp, an expm1, square roots)
// costs this much more than a white-noise kick: drag with noise against white noise alone, lambda =
// 0, 128 x 2000 particles, 2.05e7 kicks each, one thread: 1.20 s against 0.425 s (two runs each).
constexpr double kNsFlightKickExtra = 38.0;
// Under the Gaussian thermostat a real collision also updates the energy and the scale: 6.5 ns
// more (one species), 10 more (the general gas); the general gas draws a pair's class by a
// linear search, 3 ns per candidate and class beyond the first (measured as above, lambda = 0).
constexpr double kNsGaussianCollision = 6.5, kNsGasGaussianCollision = 10.0, kNsGasClass = 3.0;
// The general gas engine (dsmc/gas.cpp), from the same runs with one species written (or
// roughness) beside the one-species engine: 17 ns per candidate (it draws the class of the
// pair too), 23 more per smooth collision and 33 per rough one, 16 per kick; at an observation
// 9 ns per particle (measuring, resetting the bounds), 10 more if species are written (each
// species' rows are measured apart).
constexpr double kNsGasCandidate = 17.0, kNsGasCollision = 23.0, kNsGasRoughCollision = 33.0,
                 kNsGasKick = 16.0, kNsGasParticleObserved = 9.0, kNsGasSpeciesObserved = 10.0;
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

// The serial work of a DSMC run's output (ns): every moment sum and count of the run's record
// (its layout, built without allocating: the rows of the gas, of each species and of T_rot,
// the histograms, the steady sums, SWPM's weights per row and shell), once per run and once per
// ensemble under the record's lock; with steady_from each ensemble also averages its steady
// rows of the histograms.
double output_ns(const Config& config, double ensembles) {
  const DsmcConfig& d = config.dsmc;
  Record::Sizing size;
  layout_of(config);
  const double moments = static_cast<double>(size.moments),
               counts = static_cast<double>(size.counts);
  double ns = moments * (kNsMomentSum + ensembles * kNsEnsembleMomentSum) +
              counts * (kNsCount + ensembles * kNsEnsembleCount);
  if (d.steady && d.histogram.shells) {
    const double shells =
        (static_cast<double>(d.histogram.shells) + 1.0) * (d.histogram.component ? 2.0 : 1.0);
    ns += ensembles * shells * static_cast<double>(steady_rows(d)) * kNsSteadyRowShellEnsemble;
  }
  return ns;
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
      const double eps = std::visit([&](const auto& l) { return l.eps_of_g2(T * r * r * z); }, law);
      loss += wr * z * (1.0 - eps * eps);
      norm += wr * z;
    }
  }
  return loss / norm;
}

struct DsmcEvents {
  double collisions = 0, candidates = 0, kicks = 0;
  double ns = 0;         // one ensemble on one thread: events, steps, observations
  double events_ns = 0;  // the part of ns that is events (candidates, collisions, their kicks)
  double serial_ns = 0;  // the run's output sums (all ensembles, not in parallel)
};

// One ensemble of a DSMC config of one species (constant weights): its events.
DsmcEvents dsmc_events(const DsmcConfig& d) {
  const double n = static_cast<double>(d.particles);
  const double lambda = d.kernel.lambda, gc = d.kernel.gamma * d.kernel.C;
  const bool heated = d.thermostat == Thermostat::kWhiteNoise && d.beta > 0.0;
  const bool gaussian = d.thermostat == Thermostat::kGaussian;
  const bool split = d.scheme != Scheme::kNoSplit;
  const bool pairwise = d.majorant == MajorantKind::kPairwise;
  const double observations = static_cast<double>(d.observations());
  const double steps = split ? static_cast<double>(d.steps) : 0.0;
  // Drag and shear (physics/flight/): kicks like white noise, and (lambda > 0, no Gaussian
  // thermostat) a temperature that follows the second-moment tensor below.
  const LinearFlight flight = d.flight_of(0);
  const bool flies = d.linear_flight();
  // dT/dt = heat - B T^(1 + lambda/2): white noise heats by 2 beta, collisions cool (the moment
  // equation of a Maxwellian); the Gaussian thermostat holds T at T0, so both are 0 there.
  // In d dimensions B = area/(8d) <1 - u^.e> gamma C (1 - alpha^2) (n-1)/n E|u|^(2+lambda): pi/6
  // in d = 3; pi/8 times <1 - u^.e> = 1 (uniform) or 4/3 (hard-disk impacts) in d = 2.
  const int dim = d.dimension;
  const double loss_geometry =
      dim == 2 ? (d.geometry == Geometry::kImpact ? 4.0 / 3.0 : 1.0) / 8.0 : 1.0 / 6.0;
  const double heat = heated ? 2.0 * d.beta : 0.0;
  const double B = gaussian   ? 0.0
                   : dim == 2 ? M_PI * loss_geometry * gc * (1.0 - d.alpha * d.alpha) * (n - 1.0) /
                                    n * gaussian_moment(2.0, 2.0 + lambda, 2)
                              : M_PI * gc * (1.0 - d.alpha * d.alpha) * (n - 1.0) / (6.0 * n) *
                                    gaussian_moment(2.0, 2.0 + lambda);
  // A law of g_n (viscoelastic): the same equation with 1 - alpha^2 replaced by its Maxwellian
  // average at the current T (inelastic_fraction), so the rates follow the law's cooling. The
  // event counts for a given T(t) do not depend on the law.
  const bool constant_law = is_constant(d.restitution);
  const double B1 =
      gaussian   ? 0.0
      : dim == 2 ? M_PI * loss_geometry * gc * (n - 1.0) / n * gaussian_moment(2.0, 2.0 + lambda, 2)
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
  // With a flight: the centred second moments C, dC/dt = -nu_Pi(T) (C - T I) + (the cooling of
  // T) I - a (E C + C E^T) - 2 gamma_d C + 2 beta I, T = tr C / d, nu_Pi = (1+alpha)(3-alpha)/8
  // times the collision frequency of a particle: exact for lambda = 0 (the exact rate of Pi),
  // the Maxwellian closure otherwise; the shear heats through C_xy.
  const bool tensor = flies && !steady;
  std::array<double, 9> Cm{};
  for (int i = 0; i < dim; ++i)
    for (int j = 0; j < dim; ++j)
      Cm[3 * i + j] = d.initial_temperature_tensor.empty()
                          ? (i == j ? T0 : 0.0)
                          : d.initial_temperature_tensor[static_cast<std::size_t>(dim * i + j)];
  const double pi_factor = (1.0 + d.alpha) * (3.0 - d.alpha) / 8.0;
  auto nu_pi = [&](double T_now) { return pi_factor * 2.0 * real_rate(T_now) / n; };
  auto dC = [&](const std::array<double, 9>& X) {
    double tr = 0.0;
    for (int i = 0; i < dim; ++i) tr += X[4 * i];
    const double T_now = std::max(tr / dim, 1e-300);
    const double relax = nu_pi(T_now), cool = B_at(T_now) * std::pow(T_now, 1.0 + p);
    std::array<double, 9> r{};
    for (int i = 0; i < dim; ++i)
      for (int j = 0; j < dim; ++j) {
        double x =
            -relax * (X[3 * i + j] - (i == j ? T_now : 0.0)) - 2.0 * flight.gamma * X[3 * i + j];
        if (i == j) x += heat - cool;
        if (i == 0) x -= flight.shear * X[3 + j];
        if (j == 0) x -= flight.shear * X[3 * i + 1];
        r[3 * i + j] = x;
      }
    return r;
  };
  // No-splitting shear: the majorant of a window allows for the growth of a speed in it.
  const double window_growth =
      flight.shear != 0.0 && !split ? flight::Shear::growth(flight::Shear::kWindow) : 1.0;
  if (!std::isfinite(A * (constant_law ? B : B1) * heat * T0 * d.t_end * u0 +
                     1.0)) {  // cannot be integrated
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
    if (!steady && !tensor && std::isfinite(T_star) && std::fabs(T - T_star) <= 1e-6 * T_star) {
      steady = true;
      T = T_star;
    }
    if (!steady) {  // RK4 steps that change T by a few per cent and resolve its relaxation
      const double rate = std::fabs(dT(T)), relax = B_at(T) * (1.0 + p) * std::pow(T, p);
      if (rate > 0.0) h = std::min(h, 0.05 * T / rate);
      if (relax > 0.0) h = std::min(h, 0.05 / relax);
      if (tensor) {
        h = std::min(h, 0.05 / std::max(nu_pi(T), 1e-300));
        if (flight.shear != 0.0) h = std::min(h, 0.05 / std::fabs(flight.shear));
        if (flight.gamma > 0.0) h = std::min(h, 0.05 / flight.gamma);
      }
    }
    if (tracks_max) {  // U_max grows like sqrt(log(seen)): steps of a growing fraction of t
      const double seen_rate = 2.0 * real_rate(T);
      h = std::min(h, std::max(0.5 * t, 0.1 * n / seen_rate));
    }
    if (!(h > 0.0) || t + h == t) h = d.t_end - t;  // no progress left in double precision
    const double r0 = real_rate(T), c0 = candidate_rate(T, u_max);
    if (tensor) {
      auto add = [](const std::array<double, 9>& a, double f, const std::array<double, 9>& b) {
        std::array<double, 9> r;
        for (int k = 0; k < 9; ++k) r[k] = a[k] + f * b[k];
        return r;
      };
      const auto k1 = dC(Cm), k2 = dC(add(Cm, 0.5 * h, k1)), k3 = dC(add(Cm, 0.5 * h, k2)),
                 k4 = dC(add(Cm, h, k3));
      for (int k = 0; k < 9; ++k) Cm[k] += h / 6.0 * (k1[k] + 2 * k2[k] + 2 * k3[k] + k4[k]);
      double tr = 0.0;
      for (int i = 0; i < dim; ++i) tr += Cm[4 * i];
      T = std::max(tr / dim, 1e-300);
    } else if (!steady) {
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
      u_max = std::max(u_max,
                       window_growth * factor * std::sqrt(T_peak) * chi_expected_max(seen(t), dim));
    e.candidates += 0.5 * h * (c0 + candidate_rate(T, u_max));
    if (!std::isfinite(e.candidates)) break;
  }
  e.candidates = std::max(e.candidates, e.collisions);
  if (heated || flies) {
    if (!split)  // both partners at every candidate, all at observations (and shear windows)
      e.kicks = 2.0 * e.candidates + n * observations +
                (flight.shear != 0.0
                     ? n * std::floor(d.t_end * std::fabs(flight.shear) / flight::Shear::kWindow)
                     : 0.0);
    else
      e.kicks = n * steps;
  }
  return e;
}

// Thrown inside the estimate when a quantity it cannot represent turns up (not a config error
// by itself: estimate_run names the key).
struct NotFinite {
  std::string why;
};

// ---- The general gas (dsmc/gas.cpp: mixtures, rough particles, either dimension) ----
//
// The moment equations of the Maxwellian approximation, one translational temperature T_a per
// species and, for rough particles, one rotational temperature R_a: every species Maxwellian at
// T_a about the same bulk velocity, spins isotropic and independent of the velocities. A pair
// (a, b) collides at the rate k_ab |u|^lambda, k_ab = (gamma/n) C sigma_ab^{d-1} |S^{d-1}|, with
// u Gaussian of variance S_ab = T_a/m_a + T_b/m_b per component; the collision of
// physics/pair_collision.hpp changes the energies by quadratic forms in u, the spins and the
// velocity of a given u (mean c_a u, c_a = (T_a/m_a)/S_ab), so their means need only E|u|^lambda,
// E|u|^(lambda+2), the share gamma_n of |u|^2 that is normal (1/2 in d = 3 and for uniform disks,
// 2/3 for hard-disk impacts) and the spin variances R_a/I_a. With the normal impulse
// (1 + eps) g_n, the tangential t g_t, J = (1 + eps) g_n n + t g_t and Q = q (r_a^2 R_a/I_a +
// r_b^2 R_b/I_b) the mean square of the spins' contact velocity across n (q = 2 in d = 3, 1 in
// d = 2), per collision
//   dK_a = -m_ab c_a <(1+eps) g_n^2 + t u_t^2> + m_ab mu_b/2 <(1+eps)^2 g_n^2 + t^2 (u_t^2 + Q)>
//   dR_a = -t q m_ab r_a^2 R_a/I_a + m_ab^2 r_a^2/(2 I_a) t^2 <u_t^2 + Q>
// (<.> weighted by |u|^lambda; for one species of smooth particles this is the one-species
// equation above). White noise heats T_a by 2 beta m_a; the Gaussian thermostat rescales every
// energy by one factor that holds their sum. The equations are stiff for masses far apart, so
// they are stepped with the L-stable second-order Rosenbrock method (ROS2) and a numerical
// Jacobian, by steps that change no temperature by more than 5 % (or double one that is below a
// millionth of the largest).
//
// Candidates: class (a, b) at k_ab P_ab (R_a + R_b)^lambda, R_a the bound of species a. The
// engine resets the bounds to the exact maxima at every observation (and at every splitting step
// of a heated run), and between resets raises them to every velocity it meets after a collision:
// R_a is the expected maximum of the N_a + (velocities seen since the reset) draws of a
// Maxwellian at the highest T_a since the reset. Up to kExactResets resets are followed one by
// one; beyond, the bound is that of the middle of an interval at the current temperature.

// The share of |u|^2 along the impact normal, <(u^.n)^2>.
double normal_share(const DsmcConfig& d) {
  return d.dimension == 2 && d.geometry == Geometry::kImpact ? 2.0 / 3.0 : 0.5;
}

// <(1+eps) g_n^2> / <g_n^2> and <(1+eps)^2 g_n^2> / <g_n^2> over collisions (weight |u|^lambda)
// of a Gaussian u of variance S per component, for a law of g_n: midpoint sums over |u| = sqrt(S)
// rho (rho of the chi law with d degrees of freedom) and the impact angle.
std::pair<double, double> law_factors(const RestitutionLaw& law, double lambda, double S,
                                      const DsmcConfig& d) {
  constexpr int kR = 48, kZ = 24;
  constexpr double kRMax = 12.0;
  double a1 = 0.0, a2 = 0.0, norm = 0.0;
  for (int i = 0; i < kR; ++i) {
    const double rho = (i + 0.5) * kRMax / kR;
    const double wr = std::pow(rho, d.dimension + 1.0 + lambda) * std::exp(-0.5 * rho * rho);
    for (int k = 0; k < kZ; ++k) {
      const double x = (k + 0.5) / kZ;
      // z = (u^.n)^2: uniform on [0, 1] in d = 3 (e uniform on S^2), 1 - s^2 with s uniform for
      // hard-disk impacts, (1 - cos phi)/2 with phi uniform for uniform disks.
      const double z = d.dimension == 3                  ? x
                       : d.geometry == Geometry::kImpact ? 1.0 - x * x
                                                         : 0.5 * (1.0 - std::cos(M_PI * x));
      const double eps =
          std::visit([&](const auto& l) { return l.eps_of_g2(S * rho * rho * z); }, law);
      a1 += wr * z * (1.0 + eps);
      a2 += wr * z * (1.0 + eps) * (1.0 + eps);
      norm += wr * z;
    }
  }
  return {a1 / norm, a2 / norm};
}

constexpr double kExactResets = 1000;

class GasModel {
 public:
  explicit GasModel(const DsmcConfig& d)
      : d_(d), K_(d.species.size()), rough_(d.roughness.on), lambda_(d.kernel.lambda) {
    const double n = static_cast<double>(d.particles);
    for (const SpeciesSpec& s : d.species) {
      N_.push_back(static_cast<double>(s.count));
      m_.push_back(s.mass);
      r_.push_back(0.5 * s.diameter);
      I_.push_back(s.moment_of_inertia());
    }
    for (std::size_t a = 0; a < K_; ++a)
      for (std::size_t b = a; b < K_; ++b) {
        Class c;
        c.a = a;
        c.b = b;
        c.pairs = a == b ? 0.5 * N_[a] * (N_[a] - 1.0) : N_[a] * N_[b];
        const double sigma = r_[a] + r_[b];
        c.k = d.kernel.gamma / n * d.kernel.C * (d.dimension == 2 ? sigma : sigma * sigma) *
              d.kernel.area;
        c.alpha = d.pair_alpha(a, b);
        c.terms = pair_terms(m_[a], m_[b], d.species[a].diameter, d.species[b].diameter,
                             rough_ ? d.roughness.beta : -1.0, rough_ ? d.species[a].inertia : 0.0,
                             rough_ ? d.species[b].inertia : 0.0);
        c.m_ab = m_[a] * m_[b] / (m_[a] + m_[b]);
        classes_.push_back(c);
      }
    gn_ = normal_share(d);
    q_ = d.dimension == 2 ? 1.0 : 2.0;
    d_rot_ = d.dimension == 2 ? 1.0 : 3.0;
    heat_ = d.thermostat == Thermostat::kWhiteNoise ? 2.0 * d.beta : 0.0;
    for (std::size_t a = 0; a < d.species.size(); ++a) {
      const LinearFlight f = d.flight_of(a);
      heat_of_.push_back(d.thermostat == Thermostat::kWhiteNoise ? 2.0 * f.beta : 0.0);
      drag_of_.push_back(f.gamma);
    }
    gaussian_ = d.thermostat == Thermostat::kGaussian;
  }

  /// Throws NotFinite for a config whose particles the engine cannot represent: a thermal
  /// speed whose square (times the margin of the largest of n draws) overflows, or, for rough
  /// particles, a moment of inertia I = kappa m sigma^2/4 that underflows to 0 or gives spins
  /// or contact speeds that overflow (the engine's velocities turn into NaN, and a NaN rate
  /// never reaches the end of an interval).
  void check_scales() const {
    for (std::size_t a = 0; a < K_; ++a) {
      const std::string name = "species " + d_.species[a].name;
      if (!std::isfinite(1e4 * d_.initial_temperature / m_[a]))
        throw NotFinite{"the thermal speed of " + name + ", sqrt(T/m), overflows"};
      if (!rough_) continue;
      const double spin2 = d_.initial_rotational_temperature / I_[a];
      if (!(I_[a] >= std::numeric_limits<double>::min()) || !std::isfinite(1e4 * spin2) ||
          !std::isfinite(1e4 * spin2 * r_[a] * r_[a]))
        throw NotFinite{"the spins of " + name + ", sqrt(T_rot/I) with I = kappa m sigma^2/4 = " +
                        format_real(I_[a]) + ", overflow"};
    }
    for (const Class& c : classes_)
      if (!std::isfinite(c.k * c.pairs) ||
          !std::isfinite(c.terms.spin_a + c.terms.spin_b + c.terms.tangential))
        throw NotFinite{"the collision terms of species " + d_.species[c.a].name + " and " +
                        d_.species[c.b].name + " overflow"};
  }

  std::size_t size() const { return rough_ ? 2 * K_ : K_; }
  std::vector<double> initial() const {
    std::vector<double> x(K_, d_.initial_temperature);
    if (rough_) x.insert(x.end(), K_, d_.initial_rotational_temperature);
    return x;
  }

  // dx/dt; with `collisions`, the real collisions per unit time, and with `seen`, per species
  // the particles that take part in them per unit time.
  void rhs(const std::vector<double>& x, std::vector<double>& dx, double* collisions = nullptr,
           std::vector<double>* seen = nullptr) {
    const int dim = d_.dimension;
    dx.assign(x.size(), 0.0);
    if (collisions) *collisions = 0.0;
    if (seen) seen->assign(K_, 0.0);
    for (Class& c : classes_) {
      const std::size_t a = c.a, b = c.b;
      const double va = std::max(x[a], 0.0) / m_[a], vb = std::max(x[b], 0.0) / m_[b];
      const double S = va + vb;
      if (!(S > 0.0)) continue;
      const double rate = c.k * c.pairs * gaussian_moment(S, lambda_, dim);        // collisions
      const double flux = c.k * c.pairs * gaussian_moment(S, lambda_ + 2.0, dim);  // rate <|u|^2>
      if (collisions) *collisions += rate;
      if (seen) (*seen)[a] += rate, (*seen)[b] += rate;
      double a1 = 1.0 + c.alpha, a2 = a1 * a1;
      if (!is_constant(d_.restitution)) std::tie(a1, a2) = factors(c, S);
      const double ca = va / S, cb = vb / S, t = c.terms.tangential;
      double Q = 0.0;
      if (rough_ && t != 0.0)
        Q = q_ * (c.terms.r_a * c.terms.r_a * std::max(x[K_ + a], 0.0) / I_[a] +
                  c.terms.r_b * c.terms.r_b * std::max(x[K_ + b], 0.0) / I_[b]);
      // Per unit time: rate <g_n^2 ...> = flux gamma_n ..., rate <u_t^2> = flux (1 - gamma_n).
      const double gn2 = gn_ * flux, ut2 = (1.0 - gn_) * flux;
      const double common = a1 * gn2 + t * ut2;
      const double jj = a2 * gn2 + t * t * (ut2 + rate * Q);
      dx[a] += -c.m_ab * ca * common + 0.5 * c.m_ab * c.terms.mu_b * jj;
      dx[b] += -c.m_ab * cb * common + 0.5 * c.m_ab * c.terms.mu_a * jj;
      if (rough_ && t != 0.0) {
        const double ra2 = c.terms.r_a * c.terms.r_a, rb2 = c.terms.r_b * c.terms.r_b;
        const double spin = t * t * (ut2 + rate * Q) * c.m_ab * c.m_ab;
        dx[K_ + a] += -t * q_ * c.m_ab * ra2 * rate * std::max(x[K_ + a], 0.0) / I_[a] +
                      0.5 * spin * ra2 / I_[a];
        dx[K_ + b] += -t * q_ * c.m_ab * rb2 * rate * std::max(x[K_ + b], 0.0) / I_[b] +
                      0.5 * spin * rb2 / I_[b];
      }
    }
    // Energies per unit time into temperatures: T_a = 2 K_a/(d N_a), R_a = 2 E_a/(d_rot N_a).
    double loss = 0.0, energy = 0.0;
    for (std::size_t a = 0; a < K_; ++a) {
      loss += dx[a];
      energy += 0.5 * dim * N_[a] * std::max(x[a], 0.0);
      dx[a] *= 2.0 / (dim * N_[a]);
      if (rough_) {
        loss += dx[K_ + a];
        energy += 0.5 * d_rot_ * N_[a] * std::max(x[K_ + a], 0.0);
        dx[K_ + a] *= 2.0 / (d_rot_ * N_[a]);
      }
    }
    zeta_ = 0.0;
    if (gaussian_ && energy > 0.0) {
      zeta_ = -loss / energy;
      for (std::size_t i = 0; i < x.size(); ++i) dx[i] += zeta_ * std::max(x[i], 0.0);
    }
    // White noise heats T_a by 2 m_a beta_a, drag cools it at 2 gamma_a (per species when the
    // config maps them).
    for (std::size_t a = 0; a < K_; ++a)
      dx[a] += heat_of_[a] * m_[a] - 2.0 * drag_of_[a] * std::max(x[a], 0.0);
  }

  // Candidates per unit time with the bounds R.
  double candidate_rate(const std::vector<double>& R) const {
    double s = 0.0;
    for (const Class& c : classes_) s += c.k * c.pairs * std::pow(R[c.a] + R[c.b], lambda_);
    return s;
  }
  // The expected exact maximum of |v - V| over `draws` velocities of species a at temperature T.
  double bound(std::size_t a, double T, double draws) const {
    return std::sqrt(std::max(T, 0.0) / m_[a]) * chi_expected_max(draws, d_.dimension);
  }
  double particles(std::size_t a) const { return N_[a]; }
  /// The Gaussian thermostat's rate at the last rhs: the stored energy falls as e^(-zeta t)
  /// between the engine's folds (0 for the other thermostats).
  double zeta() const { return zeta_; }
  std::size_t species() const { return K_; }

 private:
  struct Class {
    std::size_t a = 0, b = 0;
    double pairs = 0.0, k = 0.0, alpha = 1.0, m_ab = 0.5;
    PairTerms terms;
    std::map<long, std::pair<double, double>> law;  // law_factors by ln S in steps of 1/16
  };
  // A law's factors, linear in ln S between points 1/16 apart (each computed once).
  std::pair<double, double> factors(Class& c, double S) {
    const double x = 16.0 * std::log(S);
    const double lo = std::floor(x), w = x - lo;
    auto at = [&](double k) {
      auto it = c.law.find(static_cast<long>(k));
      if (it == c.law.end())
        it = c.law
                 .emplace(static_cast<long>(k),
                          law_factors(d_.restitution, lambda_, std::exp(k / 16.0), d_))
                 .first;
      return it->second;
    };
    const auto p = at(lo), q = at(lo + 1.0);
    return {p.first + w * (q.first - p.first), p.second + w * (q.second - p.second)};
  }

  const DsmcConfig& d_;
  std::size_t K_;
  bool rough_;
  double lambda_;
  std::vector<double> N_, m_, r_, I_;
  std::vector<Class> classes_;
  double gn_ = 0.5, q_ = 2.0, d_rot_ = 3.0, heat_ = 0.0, zeta_ = 0.0;
  std::vector<double> heat_of_, drag_of_;  // per species: 2 beta_a, gamma_a
  bool gaussian_ = false;
};

// Solves A x = b (n x n, row-major) by Gaussian elimination with partial pivoting; false if
// singular.
bool solve(std::vector<double> A, std::vector<double>& b) {
  const std::size_t n = b.size();
  for (std::size_t k = 0; k < n; ++k) {
    std::size_t p = k;
    for (std::size_t i = k + 1; i < n; ++i)
      if (std::fabs(A[i * n + k]) > std::fabs(A[p * n + k])) p = i;
    if (!(std::fabs(A[p * n + k]) > 0.0)) return false;
    if (p != k) {
      for (std::size_t j = 0; j < n; ++j) std::swap(A[k * n + j], A[p * n + j]);
      std::swap(b[k], b[p]);
    }
    for (std::size_t i = k + 1; i < n; ++i) {
      const double f = A[i * n + k] / A[k * n + k];
      for (std::size_t j = k; j < n; ++j) A[i * n + j] -= f * A[k * n + j];
      b[i] -= f * b[k];
    }
  }
  for (std::size_t k = n; k-- > 0;) {
    for (std::size_t j = k + 1; j < n; ++j) b[k] -= A[k * n + j] * b[j];
    b[k] /= A[k * n + k];
  }
  return true;
}

// The mean of a positive rate over a step from its values at the ends, exact if it changes
// exponentially (as the Gaussian thermostat's bounds do): the logarithmic mean.
double step_mean(double a, double b) {
  if (!(a > 0.0 && b > 0.0) || std::fabs(a - b) <= 1e-9 * (a + b)) return 0.5 * (a + b);
  return (b - a) / std::log(b / a);
}

// One ensemble of a general-gas config: its events and their time on one thread.
DsmcEvents gas_events(const DsmcConfig& d) {
  GasModel g(d);
  g.check_scales();
  const std::size_t K = g.species(), dim = g.size();
  const double n = static_cast<double>(d.particles);
  const bool heated =
      (d.thermostat == Thermostat::kWhiteNoise && d.beta > 0.0) || d.linear_flight();
  const bool split = d.scheme != Scheme::kNoSplit;
  const double lambda = d.kernel.lambda;
  const double observations = static_cast<double>(d.observations());
  const double steps = split ? static_cast<double>(d.steps) : 0.0;
  // The bounds are reset at every observation, and at every step of a heated splitting run.
  const double resets = heated && split ? steps : observations;
  double period = d.t_end / resets;
  const bool exact = resets <= kExactResets;
  // dsmc.observe: the resets at its times, period then the gap between the two around now.
  const std::vector<double>* listed =
      !(heated && split) && !d.observe_times.empty() ? &d.observe_times : nullptr;
  std::size_t next_index = 0;
  auto gap_at = [&](double at) {
    auto it = std::upper_bound(listed->begin(), listed->end(), at);
    if (it == listed->end()) --it;
    return *it - (it == listed->begin() ? 0.0 : *(it - 1));
  };
  std::vector<double> x = g.initial(), f, seen_rate(K), peak(x.begin(), x.begin() + K);
  std::vector<double> seen(K), R(K), bound(K);
  // Under the Gaussian thermostat the engine keeps velocities and bounds in stored units that
  // shrink with the energy lost since its last fold (the true values are scaled back up): a
  // bound set at one time grows in true units as e^(zeta t/2) until the next reset, folds or not.
  double inflate = 0.0;  // ln of that growth since the reset
  auto reset = [&] {
    inflate = 0.0;
    for (std::size_t a = 0; a < K; ++a) {
      seen[a] = g.particles(a);
      peak[a] = x[a];
      R[a] = bound[a] = g.bound(a, x[a], seen[a]);
    }
  };
  // The bounds at the state x: followed from the reset (exact), or those of the middle of an
  // interval at the current temperatures.
  auto bounds_now = [&](const std::vector<double>& seen_per_time) {
    if (exact) {
      for (std::size_t a = 0; a < K; ++a) {
        peak[a] = std::max(peak[a], x[a]);
        bound[a] = std::max(bound[a], g.bound(a, peak[a], seen[a]));
        R[a] = bound[a] * std::exp(0.5 * inflate);
      }
    } else {
      for (std::size_t a = 0; a < K; ++a)
        R[a] = g.bound(a, x[a], g.particles(a) + 0.5 * period * seen_per_time[a]) *
               std::exp(0.25 * g.zeta() * period);
    }
  };
  DsmcEvents e;
  double t = 0.0, next_reset = listed ? listed->front() : period, rate = 0.0;
  if (listed) period = gap_at(t);
  reset();
  g.rhs(x, f, &rate, &seen_rate);
  double cand = lambda == 0.0 ? rate : g.candidate_rate(R);
  if (!exact) bounds_now(seen_rate), cand = lambda == 0.0 ? rate : g.candidate_rate(R);
  std::vector<double> J(dim * dim), x1(dim), f1(dim), k1(dim), k2(dim), W(dim * dim);
  std::vector<double> x_of_J;                       // the state J was taken at (none yet)
  const double gamma = 1.0 + 1.0 / std::sqrt(2.0);  // ROS2
  bool steady = false;
  for (int step = 0; t < d.t_end; ++step) {
    double h = d.t_end - t;
    if (listed) period = gap_at(t);
    // Steady: what is left would change no temperature by 1e-4; the rates then change only
    // with the bounds, the same in every interval between resets.
    double change = 0.0;
    for (std::size_t i = 0; i < dim; ++i)
      if (x[i] > 0.0) change = std::max(change, std::fabs(f[i]) / x[i]);
    if (!steady && change * (d.t_end - t) < 1e-4) steady = true;
    if (steady || step == kMaxSteps) {
      if (!exact || lambda == 0.0) {  // the rates of now to the end
        e.collisions += h * rate;
        if (listed && lambda != 0.0) {  // each gap to come with the bounds of its length
          double from = t;
          for (auto it = std::upper_bound(listed->begin(), listed->end(), t); it != listed->end();
               ++it) {
            period = *it - (it == listed->begin() ? 0.0 : *(it - 1));
            bounds_now(seen_rate);
            e.candidates += (*it - from) * g.candidate_rate(R);
            from = *it;
          }
        } else {
          e.candidates += h * cand;
        }
        break;
      }
      // One interval from the next reset on, by sixteen pieces (the bounds grow like
      // sqrt(log seen)), repeated to the end; first the rest of the current one.
      auto interval = [&](double length, bool from_reset) {
        if (from_reset) reset();
        double c = 0.0;
        for (int k = 0; k < 16; ++k) {
          for (std::size_t a = 0; a < K; ++a) seen[a] += seen_rate[a] * length / 16.0;
          inflate += g.zeta() * length / 16.0;
          const double before = g.candidate_rate(R);
          bounds_now(seen_rate);
          c += step_mean(before, g.candidate_rate(R)) * length / 16.0;
        }
        return c;
      };
      const double rest = std::min(next_reset, d.t_end) - t;
      e.candidates += interval(rest, false);
      if (listed) {
        for (std::size_t i = next_index + 1; i < listed->size(); ++i)
          e.candidates += interval((*listed)[i] - (*listed)[i - 1], true);
      } else {
        const double whole = std::round((d.t_end - std::min(next_reset, d.t_end)) / period);
        if (whole > 0.0) e.candidates += whole * interval(period, true);
      }
      e.collisions += h * rate;
      break;
    }
    // Each temperature changes by at most 5 % of itself per step, or may double while it is
    // below a millionth of the largest (T = 1 against T_rot = 10^100: the steps resolve its
    // rise, but do not crawl up 230 orders of magnitude at 5 %); one at 0 (T_rot(0) = 0) is
    // measured against a 10^-12th of the largest.
    const double largest = *std::max_element(x.begin(), x.end()), floor = 1e-12 * largest;
    std::vector<double> allowed(dim);
    for (std::size_t i = 0; i < dim; ++i) {
      allowed[i] = (x[i] >= 1e-6 * largest ? 0.05 : 1.0) * (x[i] > 0.0 ? x[i] : floor);
      if (f[i] != 0.0) h = std::min(h, allowed[i] / std::fabs(f[i]));
    }
    if (exact) h = std::min(h, next_reset - t);
    if (!(h > 0.0) || t + h == t) h = d.t_end - t;
    // ROS2: W = I - gamma h J; k1 = W^-1 f(x); k2 = W^-1 (f(x + h k1) - 2 k1);
    // x' = x + h (3 k1 + k2)/2. J by forward differences, taken again once a temperature has
    // moved by a tenth since (an older J keeps the method stable: a W-method). A step that would
    // change a temperature by more than four times its allowance, or halve it, is halved (the
    // equations are far from linear).
    bool stale = x_of_J.empty();
    for (std::size_t i = 0; i < dim && !stale; ++i)
      stale = std::fabs(x[i] - x_of_J[i]) > 0.1 * (x_of_J[i] > 0.0 ? x_of_J[i] : floor);
    auto jacobian = [&] {
      x_of_J = x;
      for (std::size_t j = 0; j < dim; ++j) {
        x1 = x;
        const double dxj = 1e-7 * (x[j] > 0.0 ? x[j] : floor) + 1e-300;
        x1[j] += dxj;
        g.rhs(x1, f1);
        for (std::size_t i = 0; i < dim; ++i) J[i * dim + j] = (f1[i] - f[i]) / dxj;
      }
    };
    if (stale) jacobian();
    std::vector<double> next(dim);
    for (int halvings = 0;; ++halvings, h *= 0.5) {
      for (std::size_t i = 0; i < dim; ++i)
        for (std::size_t j = 0; j < dim; ++j)
          W[i * dim + j] = (i == j) - gamma * h * J[i * dim + j];
      k1 = f;
      bool ok = solve(W, k1);
      for (std::size_t i = 0; i < dim; ++i) x1[i] = x[i] + h * k1[i];
      g.rhs(x1, f1);
      for (std::size_t i = 0; i < dim; ++i) k2[i] = f1[i] - 2.0 * k1[i];
      ok = ok && solve(W, k2);
      bool small = true;  // no temperature jumps by more than a fifth, nor falls below half
      for (std::size_t i = 0; i < dim; ++i) {
        next[i] = ok ? x[i] + h * (1.5 * k1[i] + 0.5 * k2[i]) : x[i] + h * f[i];
        small = small && std::fabs(next[i] - x[i]) <= 4.0 * allowed[i] && next[i] >= 0.5 * x[i];
      }
      if (small) break;
      if (x_of_J != x) {  // an older J: take it afresh before halving the step
        jacobian();
        h *= 2.0;
        continue;
      }
      if (halvings == 40) {  // a step this small is safe to take explicitly
        for (std::size_t i = 0; i < dim; ++i) next[i] = x[i] + h * f[i];
        break;
      }
    }
    const double rate0 = rate, cand0 = cand;
    const std::vector<double> seen0 = seen_rate;
    for (std::size_t i = 0; i < dim; ++i) x[i] = std::max(next[i], 0.0);
    const double zeta0 = g.zeta();
    g.rhs(x, f, &rate, &seen_rate);
    inflate += 0.5 * h * (zeta0 + g.zeta());
    for (std::size_t a = 0; a < K; ++a) seen[a] += 0.5 * h * (seen0[a] + seen_rate[a]);
    bounds_now(seen_rate);
    cand = lambda == 0.0 ? rate : g.candidate_rate(R);
    e.collisions += h * step_mean(rate0, rate);
    e.candidates += h * step_mean(cand0, cand);
    t += h;
    if (exact && t >= next_reset * (1.0 - 1e-12)) {
      t = next_reset;
      if (listed)
        next_reset = ++next_index < listed->size() ? (*listed)[next_index] : 2.0 * d.t_end;
      else
        next_reset += period;
      reset();
      cand = lambda == 0.0 ? rate : g.candidate_rate(R);
    }
    if (!std::isfinite(e.candidates + e.collisions)) break;
  }
  e.candidates = std::max(e.candidates, e.collisions);
  if (heated) e.kicks = split ? n * steps : 2.0 * e.candidates + n * observations;
  return e;
}

// The time of one ensemble's events, steps and observations on one thread (ns), and of the
// run's serial work (serial_ns): the output's sums and histograms, added under the record's
// lock or written once.
void dsmc_time(const Config& config, double ensembles, DsmcEvents& e) {
  const DsmcConfig& d = config.dsmc;
  const double n = static_cast<double>(d.particles);
  const bool heated =
      (d.thermostat == Thermostat::kWhiteNoise && d.beta > 0.0) || d.linear_flight();
  const bool gaussian = d.thermostat == Thermostat::kGaussian;
  const bool split = d.scheme != Scheme::kNoSplit;
  const double observations = static_cast<double>(d.observations());
  const double rows = observations + 1.0;
  const double steps = split ? static_cast<double>(d.steps) : 0.0;
  const double histograms = d.histogram.shells ? (d.histogram.component ? 2.0 : 1.0) : 0.0;
  // The kicks of both partners of every candidate (no splitting, beta > 0).
  const double pair_kicks = heated && !split ? 2.0 * e.candidates : 0.0;
  if (d.general()) {
    const double K = static_cast<double>(d.species.size()), classes = K * (K + 1.0) / 2.0;
    e.ns = e.candidates * (kNsGasCandidate + (classes - 1.0) * kNsGasClass) +
           e.collisions * ((d.roughness.on ? kNsGasRoughCollision : kNsGasCollision) +
                           (gaussian ? kNsGasGaussianCollision : 0.0)) +
           pair_kicks * kNsGasKick +
           n * rows *
               (kNsGasParticleObserved + (d.species_written ? kNsGasSpeciesObserved : 0.0) +
                histograms * kNsHistogramParticle);
  } else if (d.majorant == MajorantKind::kPairwise) {
    e.ns = e.candidates * ns_per_dsmc_event(n, d.majorant) +
           n * rows * (kNsPerParticleObserved + histograms * kNsHistogramParticle);
  } else {
    // The table's 37.5 ns at n <= 10^5 is the RW05 Maxwell config; larger n in proportion.
    const double cache = ns_per_dsmc_event(n, d.majorant) / 37.5;
    e.ns = cache * (e.candidates * kNsCandidate +
                    e.collisions * (kNsCollision + (gaussian ? kNsGaussianCollision : 0.0)) +
                    pair_kicks * (d.kernel.lambda > 0.0 ? kNsKick : kNsKickMaxwell)) +
           n * rows * (kNsPerParticleObserved + histograms * kNsHistogramParticle);
  }
  e.events_ns =
      e.ns - n * rows * histograms * kNsHistogramParticle -
      n * rows *
          (d.general() ? kNsGasParticleObserved + (d.species_written ? kNsGasSpeciesObserved : 0.0)
                       : kNsPerParticleObserved);
  if (split) e.ns += steps * (d.scheme == Scheme::kEuler ? kNsEulerStep : kNsStrangStep);
  if (heated) e.ns += split ? e.kicks * kNsStepKick : n * observations * kNsObservationKick;
  // Shear alone is a multiply-add (no noise, no exponential): no extra.
  if (d.linear_flight() && (d.beta > 0.0 || d.drag_gamma() > 0.0))
    e.ns += e.kicks * kNsFlightKickExtra;
  if (gaussian) e.ns += n * rows * kNsGaussianFold;
  e.serial_ns = output_ns(config, ensembles);
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

constexpr double kPilotCandidates = 1e5;
constexpr double kPilotStops = 64.0;
constexpr double kPilotSeconds = 1.0;

struct WeightedCost {
  DsmcEvents events;
  double seconds = 0.0;  // one ensemble on one thread
  bool stuck = false;    // the pilot did not pass its first stop: seconds is a lower bound
  /// A pilot that did not pass its first stop (1/kPilotStops of t_end at most) in
  /// kPilotSeconds: the run takes longer than kPilotStops times that, all that is known.
  static WeightedCost lower_bound() {
    WeightedCost c;
    c.stuck = true;
    c.seconds = kPilotSeconds * kPilotStops;
    return c;
  }
};

// One stop of the pilot: its events so far, and what the extrapolation needs besides.
struct PilotMark {
  double t, candidates, collisions, kicks, seconds;
  double observed, observation_kicks, particles;
};

// Runs the pilot, handing every stop to `emit`.
template <class Emit>
void run_pilot(const DsmcConfig& d, std::uint64_t seed, Emit&& emit) {
  // The pilot's CPU time, not the wall clock: on a machine shared with other jobs the wall
  // clock ran twice as long and the estimate with it (the other engines' costs are CPU times
  // of an otherwise idle machine too). The pilot is the only thread of its process.
  auto cpu_seconds = [] {
    timespec ts{};
    ::clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
  };
  const double start = cpu_seconds();
  const std::unique_ptr<Ensemble> engine = make_ensemble(d, seed, 0);  // the weighted engine
  Ensemble& pilot = *engine;
  const bool heated = d.thermostat == Thermostat::kWhiteNoise && d.beta > 0.0;
  const std::vector<double> times = dsmc_times(d);
  double stop_kicks = 0.0, observation_kicks = 0.0, observed = 0.0, candidates = 0.0;
  auto mark = [&](double t) {
    const EventCounts& c = pilot.counts();
    candidates = static_cast<double>(c.collisions + c.fictitious);
    emit(PilotMark{t, candidates, static_cast<double>(c.collisions),
                   static_cast<double>(c.kicks) - stop_kicks, cpu_seconds() - start, observed,
                   observation_kicks, static_cast<double>(pilot.view().particles.size())});
  };
  mark(0.0);
  for (std::size_t m = 1; m < times.size() && candidates < kPilotCandidates; ++m) {
    const double from = times[m - 1], to = times[m];
    const double pieces = std::max(1.0, std::ceil((to - from) * kPilotStops / d.t_end));
    for (double k = 1.0; k <= pieces && candidates < kPilotCandidates; ++k) {
      const double s = k == pieces ? to : from + (to - from) * k / pieces;
      pilot.advance_to(s);
      const double n = static_cast<double>(pilot.view().particles.size());
      if (heated) stop_kicks += n;  // kick_all_to(s) at the end of advance_to
      if (k == pieces) {            // an observation of the run
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
    } catch (const std::bad_alloc&) {
      // Out of memory (the parent checked what one ensemble needs, but memory is shared): the
      // stops reported so far are all there is, a lower bound if too few.
    } catch (const std::length_error&) {
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
  const WeightedCost stuck = WeightedCost::lower_bound();
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

// The most events of one kind an ensemble counts: its counters are 64-bit (and a run of that
// many events would take centuries).
constexpr double kMaxEvents = 0x1p63;

bool finite(const RunEstimate& e) {
  return std::isfinite(e.collisions) && std::isfinite(e.fictitious) && std::isfinite(e.kicks) &&
         std::isfinite(e.seconds) && e.collisions >= 0 && e.fictitious >= 0 && e.kicks >= 0 &&
         e.seconds >= 0;
}

// Why the cost of `e` cannot be bounded, or "" if it can: not finite, or more events of a kind
// per ensemble than the engines' counters hold.
std::string unbounded(const RunEstimate& e) {
  if (!finite(e)) return "overflow";
  const double N = std::max<double>(1.0, static_cast<double>(e.ensembles));
  const std::pair<const char*, double> counts[] = {
      {"collisions", e.collisions}, {"fictitious candidates", e.fictitious}, {"kicks", e.kicks}};
  for (const auto& [what, total] : counts)
    if (!(total / N < kMaxEvents))
      return "the run would take " + format_samples(total / N) + " " + what +
             " per ensemble, more than its 64-bit event counters hold (2^63)";
  return "";
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
    DsmcEvents one = d.general() ? gas_events(d) : dsmc_events(d);
    dsmc_time(config, N, one);
    serial_ns = one.serial_ns;
    if (d.weights.swpm && pilots) {
      // The constant-weight events first: a config whose cost is not finite gets no pilot.
      e.collisions = one.collisions, e.fictitious = one.candidates, e.kicks = one.kicks;
      e.seconds = one.ns;
      if (!finite(e)) return e;
      // The pilot builds ensemble 0 of the run: if that alone does not fit in the memory
      // available (N_max = 10^9 needs over 100 GB), it is not run (the bare allocation
      // failure used to end `estimate`), and the time is a lower bound.
      Config one_ensemble = config;
      one_ensemble.ensembles = 1;
      one_ensemble.shard = Shard{};
      one_ensemble.checkpoint.every_seconds = 0.0;
      const double need = static_cast<double>(estimate_memory(one_ensemble, 1));
      const double have = static_cast<double>(available_memory());
      const WeightedCost pilot = have > 0 && need > 0.9 * have ? WeightedCost::lower_bound()
                                                               : weighted_cost(d, config.seed);
      const double observe_ns = one.ns - one.events_ns;
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
  e.seconds = ns * 1e-9 / (workers > 1 ? workers * kParallelEfficiency : 1.0) + serial_ns * 1e-9 +
              kFixedSeconds;
  if (config.model == Model::kDsmc && config.dsmc.source) {
    // dsmc.initial.from: each ensemble first replays the source's, on the same workers.
    Config source = config;
    source.seed = config.dsmc.source->seed;
    source.dsmc = config.dsmc.source->dsmc;
    const RunEstimate s = estimate_unchecked(source, threads, false);
    e.collisions += s.collisions, e.fictitious += s.fictitious, e.kicks += s.kicks;
    e.seconds += s.seconds - kFixedSeconds;
  }
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
    s.push_back(
        {"dsmc.beta", d.beta, [](Config& c) { c.dsmc.beta = c.dsmc.beta > 0 ? 1.0 : 0.0; }});
    s.push_back({"dsmc.gamma", d.kernel.gamma, [](Config& c) { c.dsmc.kernel.gamma = 1.0; }});
    s.push_back({"dsmc.kernel.C", d.kernel.C, [](Config& c) { c.dsmc.kernel.C = 0.1; }});
    s.push_back({"dsmc.initial.temperature", d.initial_temperature, [](Config& c) {
                   c.dsmc.initial_temperature = 1.0;
                   c.dsmc.initial_temperature_tensor.clear();
                 }});
    s.push_back({"dsmc.t_end", d.t_end, [](Config& c) {
                   c.dsmc.observe_every /= c.dsmc.t_end;
                   for (double& t : c.dsmc.observe_times) t /= c.dsmc.t_end;
                   c.dsmc.observe_log_from /= c.dsmc.t_end;
                   c.dsmc.t_end = 1.0;
                 }});
    s.push_back({"dsmc.particles", static_cast<double>(d.particles),
                 [](Config& c) { c.dsmc.particles = 1000; }});
    if (d.shear_rate() != 0.0)
      s.push_back(
          {"dsmc.shear.rate", d.shear_rate(), [](Config& c) { c.dsmc.flights[1].value = 1.0; }});
    if (d.drag_gamma() != 0.0)
      s.push_back({"dsmc.drag.gamma", d.drag_gamma(), [](Config& c) {
                     c.dsmc.flights[0].value = 1.0;
                     c.dsmc.flights[0].per_species.clear();
                   }});
    if (d.scheme != Scheme::kNoSplit)
      s.push_back({"dsmc.steps", static_cast<double>(d.steps), [](Config& c) {
                     c.dsmc.steps = std::max<std::uint64_t>(1, c.dsmc.observations());
                   }});
    // The general gas: the species' masses and diameters, the spins' temperature and inertia.
    if (d.species_written)
      for (std::size_t a = 0; a < d.species.size(); ++a) {
        const std::string key = "dsmc.species[" + std::to_string(a) + "].";
        s.push_back(
            {key + "mass", d.species[a].mass, [a](Config& c) { c.dsmc.species[a].mass = 1.0; }});
        s.push_back({key + "diameter", d.species[a].diameter,
                     [a](Config& c) { c.dsmc.species[a].diameter = 1.0; }});
      }
    if (d.roughness.on) {
      s.push_back(
          {"dsmc.initial.rotational_temperature", d.initial_rotational_temperature,
           [](Config& c) { c.dsmc.initial_rotational_temperature = c.dsmc.initial_temperature; }});
      const double uniform = d.dimension == 2 ? 0.5 : 0.4;  // a uniform disk or sphere
      if (d.roughness.inertia_per_species) {
        for (std::size_t a = 0; a < d.species.size(); ++a)
          s.push_back({"dsmc.roughness.inertia." + d.species[a].name, d.species[a].inertia,
                       [a, uniform](Config& c) { c.dsmc.species[a].inertia = uniform; }});
      } else {
        s.push_back({"dsmc.roughness.inertia", d.roughness.inertia, [uniform](Config& c) {
                       c.dsmc.roughness.inertia = uniform;
                       for (auto& sp : c.dsmc.species) sp.inertia = uniform;
                     }});
      }
    }
  } else if (config.model == Model::kIntruder) {
    const IntruderConfig& c = config.intruder;
    s.push_back({"intruder.sample_every", c.sample_every,
                 [](Config& x) { x.intruder.sample_every = 0.0; }});
    s.push_back({"intruder.bath.a", c.bath.a, [](Config& x) { x.intruder.bath.a = 1.0; }});
    s.push_back({"intruder.density", c.density, [](Config& x) { x.intruder.density = 1.0; }});
    s.push_back({"intruder.mass", c.mass, [](Config& x) { x.intruder.mass = 1.0; }});
  } else {
    const NeedleConfig& c = config.needle;
    s.push_back(
        {"needle.sample_every", c.sample_every, [](Config& x) { x.needle.sample_every = 0.0; }});
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

namespace {

// Throws ConfigError naming the key to blame for `why`: the first (most extreme) whose tame
// value alone gives a bounded estimate, without the pilots (SWPM, needle) that the search
// would otherwise repeat.
[[noreturn]] void refuse_unbounded(const Config& config, unsigned threads, const std::string& why) {
  auto closed_form_bounded = [&](const Config& c) {
    try {
      return unbounded(estimate_unchecked(c, threads, false)).empty();
    } catch (const NotFinite&) {
      return false;
    }
  };
  // Only a pilot (SWPM) failed: no single key is to blame.
  if (closed_form_bounded(config)) throw ConfigError("the run's cost cannot be estimated: " + why);
  for (const Suspect& s : suspects(config)) {
    Config tamed = config;
    s.tame(tamed);
    if (closed_form_bounded(tamed))
      throw ConfigError(
          cut(s.key + " = " + format_real(s.value)) + ": " +
          (why == "overflow" ? "the run's cost cannot be estimated (overflow)" : why) +
          "; choose a less extreme value");
  }
  throw ConfigError("the run's cost estimate is not finite (" + why +
                    "); check the config's extreme values");
}

}  // namespace

void check_cost_bounded(const Config& config) {
  std::string why;
  try {
    why = unbounded(estimate_unchecked(config, 1, false));
  } catch (const NotFinite& x) {
    why = x.why;
  }
  if (!why.empty()) refuse_unbounded(config, 1, why);
}

RunEstimate estimate_run(const Config& config, unsigned threads) {
  std::string why = "overflow";
  try {
    const RunEstimate e = estimate_unchecked(config, threads, true);
    why = unbounded(e);
    if (why.empty()) return e;
  } catch (const NotFinite& x) {
    why = x.why;
  }
  refuse_unbounded(config, threads, why);
}

std::string describe(const RunEstimate& e) {
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "%llu ensembles: %.3g collisions, %.3g fictitious, %.3g kicks; peak memory %s; "
                "wall time %s %s on %u thread%s",
                static_cast<unsigned long long>(e.ensembles), e.collisions, e.fictitious, e.kicks,
                human_bytes(static_cast<double>(e.memory_bytes)).c_str(),
                e.lower_bound ? "more than" : "about", human_seconds(e.seconds).c_str(), e.threads,
                e.threads == 1 ? "" : "s");
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
