#include "granboltz/driver/estimate.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include <gsl/gsl_cdf.h>

#include "granboltz/driver/ensemble_driver.hpp"
#include "granboltz/driver/run.hpp"
#include "granboltz/dsmc/run.hpp"
#include "granboltz/dsmc/weighted.hpp"
#include "granboltz/random/rng.hpp"
#include "granboltz/random/samplers.hpp"
#include "granboltz/stats/gsl_errors.hpp"
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
// Observing a DSMC system (moments and radial histogram) costs about this much per particle and
// observation; at most a few per cent of a run, not benchmarked separately (assumed).
constexpr double kNsPerParticleObserved = 5.0;

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

// E|u|^p for u Gaussian in 3-D with variance s2 per component: (2 s2)^(p/2) G((3+p)/2) / G(3/2).
double gaussian_moment(double s2, double p) {
  return std::pow(2.0 * s2, 0.5 * p) * std::tgamma(0.5 * (3.0 + p)) / std::tgamma(1.5);
}

// Expected maximum of N independent |x|, x a 3-D standard Gaussian (chi with 3 degrees of
// freedom): the 1 - 1/N quantile (GSL's inverse chi-squared tail) plus the Gumbel correction
// (Euler's constant / (N pdf)).
double chi3_expected_max(double N) {
  if (N < 2) return std::sqrt(8.0 / M_PI);
  install_gsl_error_handler();
  double x = std::sqrt(gsl_cdf_chisq_Qinv(1.0 / N, 3.0));
  // Should GSL fail (it then returns NaN, not abort), the leading term of the tail serves.
  if (!std::isfinite(x)) x = std::sqrt(2.0 * std::log(N));
  const double pdf = std::sqrt(2.0 / M_PI) * x * x * std::exp(-0.5 * x * x);
  return x + 0.5772156649 / (N * pdf);
}

struct DsmcEvents {
  double collisions = 0, candidates = 0, kicks = 0;
};

// One ensemble of a DSMC config.
DsmcEvents dsmc_events(const DsmcConfig& d) {
  const double n = static_cast<double>(d.particles);
  const double lambda = d.kernel.lambda, gc = d.kernel.gamma * d.kernel.C;
  const double loss = M_PI * gc * (1.0 - d.alpha * d.alpha) * (n - 1.0) / (6.0 * n);
  auto dT = [&](double T) { return 2.0 * d.beta - loss * gaussian_moment(2.0 * T, 2.0 + lambda); };
  auto real_rate = [&](double T) {
    return 2.0 * M_PI * gc * (n - 1.0) * gaussian_moment(2.0 * T, lambda);
  };
  const bool pairwise = d.majorant == MajorantKind::kPairwise;
  const double factor = d.majorant_update == MajorantUpdate::kStrict ? 2.0 : 1.0;
  const double T0 = d.initial_temperature;
  const double u0 = 2.0 * std::sqrt(T0) * chi3_expected_max(n);  // GRW05 step 1.4
  double T = T0, t = 0.0, T_peak = T0, u_max = u0;
  DsmcEvents e;
  auto candidate_rate = [&](double T_now) {
    if (lambda == 0.0) return real_rate(T_now);
    if (pairwise) return 4.0 * M_PI * gc * (n - 1.0) * gaussian_moment(T_now, lambda);
    return 2.0 * M_PI * gc * (n - 1.0) * std::pow(u_max, lambda);
  };
  // RK4 on T; the event rates are integrated with the same steps (trapezoidal rule).
  while (t < d.t_end) {
    const double relax = std::fabs(dT(T * 1.001) - dT(T)) / (0.001 * T) + 1e-12;
    const double h = std::min({d.t_end / 2000.0, 0.02 / relax, d.t_end - t});
    const double r0 = real_rate(T), c0 = candidate_rate(T);
    const double k1 = dT(T), k2 = dT(T + 0.5 * h * k1), k3 = dT(T + 0.5 * h * k2),
                 k4 = dT(T + h * k3);
    T = std::max(T + h / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4), 1e-300);
    t += h;
    T_peak = std::max(T_peak, T);
    e.collisions += 0.5 * h * (r0 + real_rate(T));
    // U_max follows the largest |v - V| the update has seen: n initial velocities plus two new
    // ones per collision, Maxwellian at the highest temperature reached so far.
    if (!pairwise && lambda > 0.0)
      u_max =
          std::max(u_max, factor * std::sqrt(T_peak) * chi3_expected_max(n + 2.0 * e.collisions));
    e.candidates += 0.5 * h * (c0 + candidate_rate(T));
  }
  e.candidates = std::max(e.candidates, e.collisions);
  if (d.beta > 0.0) {
    if (d.scheme == Scheme::kNoSplit)  // both partners at every candidate, all at observations
      e.kicks = 2.0 * e.candidates + n * static_cast<double>(d.observations());
    else
      e.kicks = n * static_cast<double>(d.steps);
  }
  return e;
}

// SWPM (dsmc.weights: swpm): the particle number, the majorant and the split and reduction
// sweeps follow the weighted dynamics, which no closed form gives, so events and time are
// measured on a pilot, ensemble 0 of the run itself, until it has drawn kPilotCandidates
// candidates; the rates of its second half are extrapolated to t_end. The pilot stops at the
// observations (a run kicks every particle there) and at least kPilotStops times in [0, t_end];
// the kicks of its stops are not counted, those of the run's observations are added.
constexpr double kPilotCandidates = 1e5;
constexpr double kPilotStops = 64.0;

struct WeightedCost {
  DsmcEvents events;
  double seconds = 0.0;  // one ensemble on one thread
};

WeightedCost weighted_cost(const DsmcConfig& d, std::uint64_t seed) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  WeightedEnsemble pilot(d, seed, 0);
  const bool heated = d.thermostat == Thermostat::kWhiteNoise && d.beta > 0.0;
  const std::vector<double> times = dsmc_times(d);
  struct Mark {
    double t, candidates, collisions, kicks, seconds;
  };
  double stop_kicks = 0.0, observation_kicks = 0.0;
  std::vector<Mark> marks;
  auto mark = [&](double t) {
    const EventCounts& c = pilot.counts();
    marks.push_back({t, static_cast<double>(c.collisions + c.fictitious),
                     static_cast<double>(c.collisions), static_cast<double>(c.kicks) - stop_kicks,
                     std::chrono::duration<double>(Clock::now() - start).count()});
  };
  mark(0.0);
  std::size_t observed = 0;  // observations the pilot reached
  for (std::size_t m = 1; m < times.size() && marks.back().candidates < kPilotCandidates; ++m) {
    const double from = times[m - 1], to = times[m];
    const double pieces = std::max(1.0, std::ceil((to - from) * kPilotStops / d.t_end));
    for (double k = 1.0; k <= pieces && marks.back().candidates < kPilotCandidates; ++k) {
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
  const Mark& last = marks.back();
  // The rates of the pilot's second half (the particle number has left its initial value).
  const Mark* half = &marks.front();
  for (const Mark& x : marks)
    if (x.t >= 0.5 * last.t && x.t < last.t) {
      half = &x;
      break;
    }
  const double ahead = d.t_end - last.t, span = last.t - half->t;
  auto extrapolate = [&](double Mark::*x) {
    return ahead > 0.0 && span > 0.0 ? last.*x + (last.*x - half->*x) / span * ahead : last.*x;
  };
  WeightedCost cost;
  cost.events.candidates = extrapolate(&Mark::candidates);
  cost.events.collisions = extrapolate(&Mark::collisions);
  const double remaining = static_cast<double>(times.size() - 1 - observed);
  cost.events.kicks = extrapolate(&Mark::kicks) + observation_kicks +
                      (heated ? remaining * static_cast<double>(pilot.particles().size()) : 0.0);
  cost.seconds = extrapolate(&Mark::seconds);
  return cost;
}

// Per collision of a needle: rejected candidates of the thinning, Phi(|v1|, omega) against
// Phi(v_n, omega) along the free rotations. Their ratio depends on the stationary state of
// (v1, omega), which no closed form gives for an inelastic needle (equipartition overestimates
// it by 14-50 %), so it is measured on a pilot ensemble of at most 20 000 collisions (~15 ms).
double needle_fictitious_per_collision(const NeedleConfig& c) {
  if (c.waiting_time != NeedleWaitingTime::kThinning) return 0.0;
  NeedleConfig pilot = c;
  pilot.collisions = std::min<std::uint64_t>(c.collisions, 20000);
  pilot.warmup = std::min<std::uint64_t>(c.warmup, 2000);
  pilot.velocity_histogram.bins = pilot.omega_histogram.bins = 0;
  try {
    const tv06::NeedleEnsemble r = tv06::simulate_needle(pilot, 0, 0);
    return static_cast<double>(r.fictitious) / static_cast<double>(r.collisions);
  } catch (const std::exception&) {
    return 0.0;  // a pilot too short to sample: the run is short too
  }
}

// Candidates of the DSMC intruder (TV06 §4): omega_max = 2 rho max|v_i - v1| (the 1 - 1/N quantile
// of |v - v1|) over the bath velocities drawn so far (n, plus one per candidate with the `tested`
// refresh) against the mean collision rate <phi(v1)>, v1 Maxwellian at the intruder's temperature.
double intruder_dsmc_candidates(const IntruderConfig& c, double collisions) {
  double ratio = 1.0;
  tv06::intruder_exact_temperature_ratio(c, &ratio);
  const double T_B = tv06::intruder_bath_temperature(c);
  const double s1 = std::sqrt(ratio * T_B / c.mass);  // sd of v1
  double phi = 0.0;
  auto body = [&](auto bath) {
    for (int k = -40; k <= 40; ++k) {  // <phi(v1)> over v1 ~ N(0, s1^2), 81-point rule
      const double x = 0.15 * k;
      phi += 0.15 * std::exp(-0.5 * x * x) / std::sqrt(2 * M_PI) * bath.fluxes(x * s1).total();
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
    double done = 0.0, candidates = 0.0;
    const double step = std::max(1.0, collisions / 400.0);
    while (done < collisions) {
      const double h = std::min(step, collisions - done);
      const double N = c.bath_refresh == BathRefresh::kTested ? n + candidates : n;
      const double omega_max = 2.0 * c.density * quantile(N);
      candidates += h * omega_max / phi;
      done += h;
    }
    return candidates;
  };
  return c.bath.kind == BathKind::kGaussian ? body(tv06::gaussian_bath(c.bath.a, c.density))
                                            : body(tv06::power_law_bath(c.bath.a, c.density));
}

std::string human_seconds(double s) {
  char buf[32];
  if (s < 120)
    std::snprintf(buf, sizeof buf, "%.2g s", s);
  else if (s < 7200)
    std::snprintf(buf, sizeof buf, "%.1f min", s / 60);
  else if (s < 3 * 86400)
    std::snprintf(buf, sizeof buf, "%.1f h", s / 3600);
  else
    std::snprintf(buf, sizeof buf, "%.1f days", s / 86400);
  return buf;
}

}  // namespace

RunEstimate estimate_run(const Config& config, unsigned threads) {
  RunEstimate e;
  e.ensembles = config.last_ensemble() - config.first_ensemble();
  e.threads = resolve_threads(threads, e.ensembles);
  e.memory_bytes = estimate_memory(config, e.threads);
  const double N = static_cast<double>(e.ensembles);
  double ns = 0.0;  // one thread, all ensembles
  if (config.model == Model::kDsmc) {
    const DsmcConfig& d = config.dsmc;
    const double n = static_cast<double>(d.particles);
    DsmcEvents one;
    if (d.weights.swpm) {
      const WeightedCost pilot = weighted_cost(d, config.seed);
      one = pilot.events;
      ns = N * pilot.seconds * 1e9;
    } else {
      one = dsmc_events(d);
      ns = N * (one.candidates * ns_per_dsmc_event(n, d.majorant) +
                n * static_cast<double>(d.observations() + 1) * kNsPerParticleObserved);
    }
    e.collisions = N * one.collisions;
    e.fictitious = N * (one.candidates - one.collisions);
    e.kicks = N * one.kicks;
  } else if (config.model == Model::kIntruder) {
    const IntruderConfig& c = config.intruder;
    const double per = static_cast<double>(c.warmup + c.collisions);
    e.collisions = N * per;
    if (c.method == IntruderMethod::kDsmc) {
      const double candidates = intruder_dsmc_candidates(c, per);
      e.fictitious = N * std::max(0.0, candidates - per);
      ns = N * candidates * kNsIntruderDsmc;
    } else {
      ns = e.collisions * kNsIntruderGillespie;
    }
  } else {
    const NeedleConfig& c = config.needle;
    e.collisions = N * static_cast<double>(c.warmup + c.collisions);
    e.fictitious = e.collisions * needle_fictitious_per_collision(c);
    ns = (e.collisions + e.fictitious) * kNsNeedle;
  }
  const double workers = std::min<double>(e.threads, std::max(N, 1.0));
  e.seconds = ns * 1e-9 / (workers > 1 ? workers * kParallelEfficiency : 1.0);
  return e;
}

std::string describe(const RunEstimate& e) {
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "%llu ensembles: %.3g collisions, %.3g fictitious, %.3g kicks; peak memory %s; "
                "wall time about %s on %u thread%s",
                static_cast<unsigned long long>(e.ensembles), e.collisions, e.fictitious, e.kicks,
                human_bytes(static_cast<double>(e.memory_bytes)).c_str(),
                human_seconds(e.seconds).c_str(), e.threads, e.threads == 1 ? "" : "s");
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
