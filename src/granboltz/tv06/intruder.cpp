// Event loops of the 1-D intruder (TV06 §3.1 Gillespie, §4 DSMC) for one ensemble.
#include "granboltz/tv06/intruder.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "granboltz/random/rng.hpp"

namespace granboltz::tv06 {

namespace {

constexpr std::uint64_t kProgressEvery = 1u << 16;

/// What both methods accumulate after the warm-up: TV06's averages at equal time intervals.
class IntruderAverages {
 public:
  IntruderAverages(const IntruderConfig& c, double dt) : hist_(c.histogram), dt_(dt) {}

  void start(double t) {
    clock_.start(t, dt_, "intruder.sample_every");
    t0_ = t;
  }
  /// The intruder moved at v1 until the event at t.
  void advance(double t, double v1) {
    const std::uint64_t n = clock_.count_before(t);
    if (n == 0) return;
    const double w = static_cast<double>(n);
    sum_v_.add(w * v1);
    sum_v2_.add(w * v1 * v1);
    hist_.add(v1, n);
    samples_ += n;
  }
  void finish(double t, double mass, double bath_temperature, IntruderEnsemble* r) {
    if (samples_ == 0)
      throw std::runtime_error(
          "intruder: no sample time fell inside the run; increase collisions or decrease "
          "sample_every");
    const double n = static_cast<double>(samples_);
    r->temperature_ratio = mass * (sum_v2_.value() / n) / bath_temperature;
    r->mean_velocity = sum_v_.value() / n;
    r->samples = samples_;
    r->time = t - t0_;
    r->histogram = std::move(hist_);
  }

 private:
  SampleClock clock_;
  CompensatedSum sum_v_, sum_v2_;
  Histogram hist_;
  double dt_, t0_ = 0.0;
  std::uint64_t samples_ = 0;
};

void report(ProgressSlot* slot, std::uint64_t done, std::uint64_t total) {
  if (slot && done % kProgressEvery == 0)
    slot->store(static_cast<double>(done) / static_cast<double>(total));
}

/// TV06 §3.1 pseudocode, one iteration per collision.
template <IntruderBath B>
IntruderEnsemble run_gillespie(const B& bath, const IntruderConfig& c, std::uint64_t seed,
                               std::uint64_t ensemble, ProgressSlot* slot) {
  Engine eng = make_stream(seed, ensemble, Consumer::kIntruder);
  IntruderAverages avg(c, intruder_sample_interval(c));
  const std::uint64_t total = c.warmup + c.collisions;
  double v1 = 0.0, t = 0.0;
  for (std::uint64_t i = 0; i < total; ++i) {
    if (i == c.warmup) avg.start(t);
    const IntruderCollision col = next_collision(bath, v1, eng);  // steps 1, 3, 4
    t += col.wait;                                                // step 2
    if (i >= c.warmup) avg.advance(t, v1);
    v1 = intruder_velocity_after(v1, col.bath_velocity, c.mass, c.alpha);  // step 5
    report(slot, i + 1, total);
  }
  IntruderEnsemble r;
  avg.finish(t, c.mass, bath.temperature(), &r);
  r.collisions = c.collisions;
  r.draws = eng.draws();
  return r;
}

/// TV06 §4. Candidates arrive at rate omega_max; each picks a side sigma and a bath particle i
/// at random and becomes a collision with probability Theta(sigma v_i1) omega_i1 / omega_max,
/// omega_i1 = 2 rho |v_i - v1|. The rate of collisions with particle i is then
/// rho |v_i - v1| / n, whose sum over an n-particle bath drawn from f has mean phi(v1).
/// omega_max is raised to omega_i1 when exceeded, as in the paper (counted: such a candidate
/// should have had a probability above 1).
template <IntruderBath B>
IntruderEnsemble run_dsmc(const B& bath, const IntruderConfig& c, std::uint64_t seed,
                          std::uint64_t ensemble, ProgressSlot* slot) {
  Engine eng = make_stream(seed, ensemble, Consumer::kIntruder);
  Engine bath_eng = make_stream(seed, ensemble, Consumer::kBath);
  const std::uint64_t n = c.bath_particles;
  std::vector<double> v(n);
  for (auto& x : v) x = bath.sample(bath_eng);
  const double two_rho = 2.0 * c.density;
  double v1 = 0.0, t = 0.0;
  double omega_max = 0.0;
  for (double x : v) omega_max = std::max(omega_max, two_rho * std::fabs(x - v1));
  if (!(omega_max > 0)) omega_max = two_rho * std::sqrt(bath.temperature());

  IntruderAverages avg(c, intruder_sample_interval(c));
  IntruderEnsemble r;
  const std::uint64_t total = c.warmup + c.collisions;
  std::uint64_t done = 0;
  if (c.warmup == 0) avg.start(t);
  while (done < total) {
    t += exponential(eng) / omega_max;
    const bool from_left = (eng() >> 63) != 0;  // sigma = +1: hit on the left (minus) side
    const std::uint64_t i = uniform_index(eng, n);
    const double vb = v[i];
    const double u = vb - v1;
    const double omega = two_rho * std::fabs(u);
    if (omega > omega_max) {
      omega_max = omega;
      if (done >= c.warmup) ++r.majorant_exceeded;
    }
    const bool approaching = from_left ? u > 0 : u < 0;
    const bool accept = approaching && uniform01(eng) * omega_max < omega;
    if (c.bath_refresh == BathRefresh::kTested ||
        (accept && c.bath_refresh == BathRefresh::kCollided))
      v[i] = bath.sample(bath_eng);
    if (!accept) {
      if (done >= c.warmup) ++r.fictitious;
      continue;
    }
    if (done >= c.warmup) avg.advance(t, v1);
    v1 = intruder_velocity_after(v1, vb, c.mass, c.alpha);
    ++done;
    if (done == c.warmup) avg.start(t);  // the warm-up ends with its last collision
    report(slot, done, total);
  }
  avg.finish(t, c.mass, bath.temperature(), &r);
  r.collisions = c.collisions;
  r.omega_max = omega_max;
  r.draws = eng.draws() + bath_eng.draws();
  return r;
}

}  // namespace

double intruder_bath_temperature(const IntruderConfig& c) {
  return c.bath.kind == BathKind::kGaussian ? gaussian_bath(c.bath.a, c.density).temperature()
                                            : power_law_bath(c.bath.a, c.density).temperature();
}

double intruder_sample_interval(const IntruderConfig& c) {
  if (c.sample_every > 0) return c.sample_every;
  const double phi0 = c.bath.kind == BathKind::kGaussian
                          ? gaussian_bath(c.bath.a, c.density).fluxes(0.0).total()
                          : power_law_bath(c.bath.a, c.density).fluxes(0.0).total();
  return 1.0 / phi0;
}

bool intruder_exact_temperature_ratio(const IntruderConfig& c, double* ratio) {
  if (c.bath.kind == BathKind::kGaussian) {
    *ratio = (1.0 + c.alpha) / (2.0 + (1.0 - c.alpha) / c.mass);
    return true;
  }
  if (c.mass == c.alpha) {
    *ratio = c.alpha;
    return true;
  }
  return false;
}

IntruderEnsemble simulate_intruder(const IntruderConfig& c, std::uint64_t seed,
                                   std::uint64_t ensemble, ProgressSlot* slot) {
  const bool dsmc = c.method == IntruderMethod::kDsmc;
  if (c.bath.kind == BathKind::kGaussian) {
    const GaussianBath bath = gaussian_bath(c.bath.a, c.density);
    return dsmc ? run_dsmc(bath, c, seed, ensemble, slot)
                : run_gillespie(bath, c, seed, ensemble, slot);
  }
  const PowerLawBath bath = power_law_bath(c.bath.a, c.density);
  return dsmc ? run_dsmc(bath, c, seed, ensemble, slot)
              : run_gillespie(bath, c, seed, ensemble, slot);
}

}  // namespace granboltz::tv06
