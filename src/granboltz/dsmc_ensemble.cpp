#include "granboltz/dsmc_ensemble.hpp"

#include <algorithm>
#include <cmath>

#include "granboltz/collision.hpp"
#include "granboltz/heating.hpp"
#include "granboltz/samplers.hpp"

namespace granboltz {

namespace {
// Progress is published every this many events: cheap, and frequent enough for a human.
constexpr std::uint64_t kProgressEvery = 1u << 20;
}  // namespace

DsmcEnsemble::DsmcEnsemble(const DsmcConfig& config, std::uint64_t seed, std::uint64_t ensemble,
                           ProgressSlot* progress)
    : c_(config),
      p_(config.particles),
      heated_(config.beta > 0.0),
      track_majorant_(config.kernel.lambda > 0.0),
      events_(make_stream(seed, ensemble, Consumer::kEvents)),
      pairs_(make_stream(seed, ensemble, Consumer::kPairs)),
      sweep_(make_stream(seed, ensemble, Consumer::kSweep)),
      progress_(progress) {
  Engine init = make_stream(seed, ensemble, Consumer::kInitial);
  const double sd = std::sqrt(c_.initial_temperature);
  Vec3 sum;
  for (auto& q : p_) {
    q.v = sd * normal3(init);
    q.t = 0.0;
    sum += q.v;
  }
  v0_ = (1.0 / static_cast<double>(p_.size())) * sum;
  double r2 = 0.0;
  for (const auto& q : p_) r2 = std::max(r2, norm2(q.v - v0_));
  u_max_ = 2.0 * std::sqrt(r2);
  update_rate();
}

std::uint64_t DsmcEnsemble::random_draws() const {
  return events_.draws() + pairs_.draws() + sweep_.draws();
}

void DsmcEnsemble::update_rate() {
  rate_ = c_.kernel.majorant_rate(static_cast<double>(p_.size()), u_max_);
}

void DsmcEnsemble::adapt_majorant(const Particle& a) {
  // RW05 eq. (21) with the paper's factor 1, or the strict bound 2|v - V| >= |v - w|.
  const double factor = c_.majorant_update == MajorantUpdate::kStrict ? 2.0 : 1.0;
  const double r = factor * norm(a.v - v0_);
  if (r > u_max_) {
    u_max_ = r;
    update_rate();
  }
}

void DsmcEnsemble::adapt_majorant_all() {
  if (!track_majorant_) return;
  for (const auto& q : p_) adapt_majorant(q);
}

void DsmcEnsemble::kick(Particle& p, double t) {
  if (!heated_) return;
  const double dt = t - p.t;
  if (dt > 0.0) p.v = white_noise_kick(p.v, c_.beta, dt, events_);
  p.t = t;
  ++counts_.kicks;
}

bool DsmcEnsemble::try_collide(Particle& a, Particle& b) {
  if (track_majorant_) {
    const double u = norm(a.v - b.v);
    if (uniform01(events_) >= c_.kernel.acceptance(u, u_max_)) {
      ++counts_.fictitious;
      return false;
    }
  }
  collide(a.v, b.v, unit_vector(events_), c_.alpha);
  ++counts_.collisions;
  if (track_majorant_) {
    adapt_majorant(a);
    adapt_majorant(b);
  }
  return true;
}

void DsmcEnsemble::advance_nosplit(double s) {
  const std::uint64_t n = p_.size();
  std::uint64_t events = 0;
  for (;;) {
    const double tau = exponential(events_) / rate_;
    if (t_ + tau >= s) break;
    t_ += tau;
    const std::uint64_t i = uniform_index(pairs_, n);
    std::uint64_t j = uniform_index(pairs_, n - 1);
    if (j >= i) ++j;
    Particle& a = p_[i];
    Particle& b = p_[j];
    kick(a, t_);  // GRW05 step 2.5: kick both partners up to the event time
    kick(b, t_);
    if (track_majorant_ && heated_) {  // step 2.7
      adapt_majorant(a);
      adapt_majorant(b);
    }
    try_collide(a, b);  // steps 2.8-2.10
    if (++events % kProgressEvery == 0) report(t_);
  }
  kick_all_to(s);  // step 3.1 / Remark 2
  t_ = s;
}

void DsmcEnsemble::kick_all_to(double s) {
  if (heated_) {
    for (auto& q : p_) {
      const double dt = s - q.t;
      if (dt > 0.0) q.v = white_noise_kick(q.v, c_.beta, dt, sweep_);
      q.t = s;
    }
    counts_.kicks += p_.size();
    adapt_majorant_all();
  } else {
    for (auto& q : p_) q.t = s;
  }
}

void DsmcEnsemble::collide_during(double h) {
  const std::uint64_t n = p_.size();
  double t = 0.0;
  std::uint64_t events = 0;
  for (;;) {
    t += exponential(events_) / rate_;
    if (t >= h) break;
    const std::uint64_t i = uniform_index(pairs_, n);
    std::uint64_t j = uniform_index(pairs_, n - 1);
    if (j >= i) ++j;
    try_collide(p_[i], p_[j]);
    if (++events % kProgressEvery == 0) report(t_ + t);
  }
}

void DsmcEnsemble::kick_all_by(double h) {
  if (!heated_) return;
  for (auto& q : p_) q.v = white_noise_kick(q.v, c_.beta, h, sweep_);
  counts_.kicks += p_.size();
  adapt_majorant_all();
}

void DsmcEnsemble::advance_to(double s) {
  if (c_.scheme == Scheme::kNoSplit) {
    advance_nosplit(s);
  } else {
    const double dt = c_.time_step();
    // Steps are counted from t = 0 so that t_k = k dt carries no accumulated round-off.
    auto k = static_cast<std::uint64_t>(std::llround(t_ / dt));
    const auto k_end = static_cast<std::uint64_t>(std::llround(s / dt));
    for (; k < k_end; ++k) {
      if (c_.scheme == Scheme::kEuler) {  // RW05 Algorithm 1
        collide_during(dt);
        kick_all_by(dt);
      } else {  // RW05 Algorithm 2
        collide_during(0.5 * dt);
        kick_all_by(dt);
        collide_during(0.5 * dt);
      }
      t_ = static_cast<double>(k + 1) * dt;
      report(t_);
    }
    t_ = s;
  }
  report(t_);
}

}  // namespace granboltz
