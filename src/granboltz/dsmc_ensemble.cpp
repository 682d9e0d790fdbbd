#include "granboltz/dsmc_ensemble.hpp"

#include <algorithm>
#include <cmath>

#include "granboltz/collision.hpp"
#include "granboltz/heating.hpp"
#include "granboltz/samplers.hpp"

namespace granboltz {

namespace {
// Progress is published every this many events: cheap, and frequent enough for a human.
constexpr std::uint64_t kProgressMask = (1u << 20) - 1;

// The lambda cases with a loop of their own: Maxwell molecules, hard spheres, lambda = 1/2, other.
constexpr int kMaxwell = 0, kHardSpheres = 1, kHalf = 2, kGeneral = 3;
int lambda_case(double lambda) {
  return lambda == 0.0 ? kMaxwell : lambda == 1.0 ? kHardSpheres : lambda == 0.5 ? kHalf : kGeneral;
}
}  // namespace

DsmcEnsemble::DsmcEnsemble(const DsmcConfig& config, std::uint64_t seed, std::uint64_t ensemble,
                           ProgressSlot* progress)
    : c_(config),
      p_(config.particles),
      adapt_factor2_(config.majorant_update == MajorantUpdate::kStrict ? 4.0 : 1.0),
      heated_(config.beta > 0.0),
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
  set_majorant(2.0 * std::sqrt(r2));
  for (auto& pair : ring_) pair = draw_pair(pairs_);
}

std::uint64_t DsmcEnsemble::random_draws() const {
  return events_.draws() + pairs_.draws() + sweep_.draws();
}

void DsmcEnsemble::set_majorant(double u_max) {
  u_max_ = u_max;
  u_max2_ = u_max * u_max;
  inv_rate_ = 1.0 / c_.kernel.majorant_rate(static_cast<double>(p_.size()), u_max_);
}

void DsmcEnsemble::adapt_majorant(const Particle& a) {
  // RW05 eq. (21) with the paper's factor 1, or the strict bound 2|v - V| >= |v - w|.
  const double r2 = adapt_factor2_ * norm2(a.v - v0_);
  if (r2 > u_max2_) set_majorant(std::sqrt(r2));
}

void DsmcEnsemble::adapt_majorant_all() {
  if (c_.kernel.lambda == 0.0) return;  // U_max plays no role for Maxwell molecules
  for (const auto& q : p_) adapt_majorant(q);
}

DsmcEnsemble::Pair DsmcEnsemble::draw_pair(Engine& pairs) {
  // i uniform on {0..n-1}, j uniform on the others (GRW05 steps 2.3-2.4).
  const auto n = static_cast<std::uint32_t>(p_.size());
  Pair pair;
  uniform_index_pair(pairs, n, n - 1, pair.i, pair.j);
  if (pair.j >= pair.i) ++pair.j;
  return pair;
}

inline DsmcEnsemble::Pair DsmcEnsemble::next_pair(Engine& pairs) {
  const Pair pair = ring_[head_];
  const Pair ahead = draw_pair(pairs);
  ring_[head_] = ahead;
  head_ = (head_ + 1) % kLookahead;
  __builtin_prefetch(&p_[ahead.i], 1);
  __builtin_prefetch(&p_[ahead.j], 1);
  return pair;
}

template <int kLambda>
inline bool DsmcEnsemble::accept(double u2, Engine& events) {
  // Accept with probability (|u|/U_max)^lambda, 1 when |u| >= U_max (RW05 eq. 19), comparing
  // squares to avoid square roots.
  const double r = uniform01(events);
  if constexpr (kLambda == kHardSpheres) {
    return r * r * u_max2_ < u2;
  } else if constexpr (kLambda == kHalf) {
    const double r2 = r * r;
    return r2 * r2 * u_max2_ < u2;
  } else {
    return u2 >= u_max2_ || r < std::pow(u2 / u_max2_, 0.5 * c_.kernel.lambda);
  }
}

template <bool kHeated, int kLambda>
void DsmcEnsemble::run_nosplit(double s) {
  const double alpha = c_.alpha, beta = c_.beta;
  // Local copies of the streams: kept in registers instead of being stored after every draw.
  Engine ev = events_, pairs = pairs_;
  std::uint64_t events = 0;
  for (;;) {
    const double tau = exponential(ev) * inv_rate_;  // GRW05 step 2.1
    if (t_ + tau >= s) break;
    t_ += tau;
    const Pair pair = next_pair(pairs);
    Particle& a = p_[pair.i];
    Particle& b = p_[pair.j];
    if constexpr (kHeated) {  // step 2.5: kick both partners up to the event time
      white_noise_kick2(a.v, t_ - a.t, b.v, t_ - b.t, beta, ev);
      a.t = t_;
      b.t = t_;
      counts_.kicks += 2;
      if constexpr (kLambda != kMaxwell) {  // step 2.7
        adapt_majorant(a);
        adapt_majorant(b);
      }
    }
    if constexpr (kLambda != kMaxwell) {  // step 2.8
      if (!accept<kLambda>(norm2(a.v - b.v), ev)) {
        ++counts_.fictitious;
        if ((++events & kProgressMask) == 0) report(t_);
        continue;
      }
    }
    collide(a.v, b.v, unit_vector(ev), alpha);  // step 2.9
    ++counts_.collisions;
    if constexpr (kLambda != kMaxwell) {  // step 2.10
      adapt_majorant(a);
      adapt_majorant(b);
    }
    if ((++events & kProgressMask) == 0) report(t_);
  }
  events_ = ev;
  pairs_ = pairs;
}

void DsmcEnsemble::kick_all_to(double s) {
  if (heated_) {
    Engine sweep = sweep_;
    const std::size_t n = p_.size();
    for (std::size_t k = 0; k + 1 < n; k += 2) {
      white_noise_kick2(p_[k].v, s - p_[k].t, p_[k + 1].v, s - p_[k + 1].t, c_.beta, sweep);
      p_[k].t = p_[k + 1].t = s;
    }
    if (n % 2) {
      p_[n - 1].v = white_noise_kick(p_[n - 1].v, c_.beta, s - p_[n - 1].t, sweep);
      p_[n - 1].t = s;
    }
    sweep_ = sweep;
    counts_.kicks += p_.size();
    adapt_majorant_all();
  } else {
    for (auto& q : p_) q.t = s;
  }
}

template <int kLambda>
void DsmcEnsemble::collide_during(double h) {
  const double alpha = c_.alpha;
  Engine ev = events_, pairs = pairs_;
  double t = 0.0;
  std::uint64_t events = 0;
  for (;;) {
    t += exponential(ev) * inv_rate_;
    if (t >= h) break;
    const Pair pair = next_pair(pairs);
    Particle& a = p_[pair.i];
    Particle& b = p_[pair.j];
    if constexpr (kLambda != kMaxwell) {
      if (!accept<kLambda>(norm2(a.v - b.v), ev)) {
        ++counts_.fictitious;
        continue;
      }
    }
    collide(a.v, b.v, unit_vector(ev), alpha);
    ++counts_.collisions;
    if constexpr (kLambda != kMaxwell) {
      adapt_majorant(a);
      adapt_majorant(b);
    }
    if ((++events & kProgressMask) == 0) report(t_ + t);
  }
  events_ = ev;
  pairs_ = pairs;
}

void DsmcEnsemble::kick_all_by(double h) {
  if (!heated_) return;
  Engine sweep = sweep_;
  const std::size_t n = p_.size();
  for (std::size_t k = 0; k + 1 < n; k += 2)
    white_noise_kick2(p_[k].v, h, p_[k + 1].v, h, c_.beta, sweep);
  if (n % 2) p_[n - 1].v = white_noise_kick(p_[n - 1].v, c_.beta, h, sweep);
  sweep_ = sweep;
  counts_.kicks += p_.size();
  adapt_majorant_all();
}

void DsmcEnsemble::advance_to(double s) {
  const int lc = lambda_case(c_.kernel.lambda);
  if (c_.scheme == Scheme::kNoSplit) {
    switch (lc + 4 * heated_) {
      case kMaxwell: run_nosplit<false, kMaxwell>(s); break;
      case kHardSpheres: run_nosplit<false, kHardSpheres>(s); break;
      case kHalf: run_nosplit<false, kHalf>(s); break;
      case kGeneral: run_nosplit<false, kGeneral>(s); break;
      case 4 + kMaxwell: run_nosplit<true, kMaxwell>(s); break;
      case 4 + kHardSpheres: run_nosplit<true, kHardSpheres>(s); break;
      case 4 + kHalf: run_nosplit<true, kHalf>(s); break;
      default: run_nosplit<true, kGeneral>(s); break;
    }
    kick_all_to(s);  // step 3.1 / Remark 2
    t_ = s;
  } else {
    auto collide_for = [&](double h) {
      switch (lc) {
        case kMaxwell: collide_during<kMaxwell>(h); break;
        case kHardSpheres: collide_during<kHardSpheres>(h); break;
        case kHalf: collide_during<kHalf>(h); break;
        default: collide_during<kGeneral>(h); break;
      }
    };
    const double dt = c_.time_step();
    // Steps are counted from t = 0 so that t_k = k dt carries no accumulated round-off.
    auto k = static_cast<std::uint64_t>(std::llround(t_ / dt));
    const auto k_end = static_cast<std::uint64_t>(std::llround(s / dt));
    for (; k < k_end; ++k) {
      if (c_.scheme == Scheme::kEuler) {  // RW05 Algorithm 1
        collide_for(dt);
        kick_all_by(dt);
      } else {  // RW05 Algorithm 2
        collide_for(0.5 * dt);
        kick_all_by(dt);
        collide_for(0.5 * dt);
      }
      t_ = static_cast<double>(k + 1) * dt;
      report(t_);
    }
    t_ = s;
  }
  report(t_);
}

}  // namespace granboltz
