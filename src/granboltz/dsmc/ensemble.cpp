#include "granboltz/dsmc/ensemble.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "granboltz/core/hot.hpp"
#include "granboltz/dsmc/initial_state.hpp"
#include "granboltz/dsmc/particles_io.hpp"
#include "granboltz/physics/collision.hpp"
#include "granboltz/physics/flight/shear.hpp"
#include "granboltz/physics/geometry.hpp"
#include "granboltz/physics/heating.hpp"
#include "granboltz/physics/restitution/collide.hpp"
#include "granboltz/random/samplers.hpp"

namespace granboltz {

namespace {
// Progress is published every this many events: cheap, and frequent enough for a human.
constexpr std::uint64_t kProgressMask = (1u << 20) - 1;
// A requested pause is noticed within this many events (well under a millisecond).
constexpr std::uint64_t kPauseMask = (1u << 14) - 1;

// The no-splitting loop's marker for drag or shear: its kicks are the flight's propagator.
struct LinearFlightKicks {
  static constexpr bool kKicks = true;
  static constexpr bool kLazyScale = false;
};

// The lambda cases with a loop of their own: Maxwell molecules, hard spheres, lambda = 1/2, other.
constexpr int kMaxwell = 0, kHardSpheres = 1, kHalf = 2, kGeneral = 3;
int lambda_case(double lambda) {
  return lambda == 0.0 ? kMaxwell : lambda == 1.0 ? kHardSpheres : lambda == 0.5 ? kHalf : kGeneral;
}

// Gaussian thermostat: the scale is folded into the velocities once s^2 exceeds this, i.e. once
// the stored velocities have cooled by 2^8 (some 20 collisions per particle at alpha = 1/2). The
// running energy then never falls far below the values it was summed from (it would lose all
// its digits after a cooling by ~10^12), and the O(n) fold costs about 1 % of the events.
constexpr double kRefold = 0x1p8;

// s^-lambda from s^2, the same arithmetic whether lc is a constant or not.
inline double inverse_power(int lc, double lambda, double s2) {
  switch (lc) {
    case kMaxwell:
      return 1.0;
    case kHardSpheres:
      return 1.0 / std::sqrt(s2);
    case kHalf:
      return 1.0 / std::sqrt(std::sqrt(s2));
    default:
      return std::pow(s2, -0.5 * lambda);
  }
}
}  // namespace

DsmcEnsemble::DsmcEnsemble(const DsmcConfig& config, std::uint64_t seed, std::uint64_t ensemble,
                           ProgressSlot* progress)
    : c_(config),
      p_(config.particles),
      adapt_factor2_(config.majorant_update == MajorantUpdate::kStrict ? 4.0 : 1.0),
      heated_(config.thermostat == Thermostat::kWhiteNoise && config.beta > 0.0),
      gaussian_(config.thermostat == Thermostat::kGaussian),
      events_(make_stream(seed, ensemble, Consumer::kEvents)),
      pairs_(make_stream(seed, ensemble, Consumer::kPairs)),
      sweep_(make_stream(seed, ensemble, Consumer::kSweep)),
      pairwise_(config.majorant == MajorantKind::kPairwise),
      progress_(progress),
      flight_(config.flight_of(0)),
      linear_(config.linear_flight()) {
  Engine init = make_stream(seed, ensemble, Consumer::kInitial);
  const double sd = std::sqrt(c_.initial_temperature);
  const PreparedStart start = prepared_start(c_.initial_temperature_tensor, c_.initial_heat_flux,
                                             c_.dimension, c_.initial_temperature);
  Vec3 sum;
  for (auto& q : p_) {
    if (const auto v = start.velocity(1.0, init)) {
      q.v = *v;
    } else if (c_.dimension == 2) {
      const double x = normal(init);
      const double y = normal(init);
      q.v = {sd * x, sd * y, 0.0};
    } else {
      q.v = sd * normal3(init);
    }
    q.t = 0.0;
    sum += q.v;
  }
  v0_ = (1.0 / static_cast<double>(p_.size())) * sum;
  if (linear_) set_flight_frame();
  if (gaussian_) fold_scale();  // the thermostat holds T at T0 exactly, from t = 0 on
  double r2 = 0.0;
  for (const auto& q : p_) r2 = std::max(r2, norm2(q.v - v0_));
  set_majorant(2.0 * growth_ * std::sqrt(r2));
  if (pairwise_) {
    w_.resize(p_.size());
    reweigh_all();
    const auto n = static_cast<std::uint32_t>(p_.size());
    candidates_ = IndexStream(seed, ensemble, Consumer::kCandidates, n);
    partners_ = IndexStream(seed, ensemble, Consumer::kPartners, n - 1);
  } else {
    for (auto& pair : ring_) pair = draw_pair(pairs_);
  }
  set_tracking();
  resum();
}

void DsmcEnsemble::set_velocities(const std::vector<Vec3>& v) {
  Vec3 sum;
  for (std::size_t i = 0; i < p_.size(); ++i) {
    p_[i].v = v[i];
    p_[i].t = t_;
    sum += v[i];
  }
  v0_ = linear_ ? Vec3{} : (1.0 / static_cast<double>(p_.size())) * sum;
  if (gaussian_) fold_scale();
  double r2 = 0.0;
  for (const auto& q : p_) r2 = std::max(r2, norm2(q.v - v0_));
  set_majorant(2.0 * growth_ * std::sqrt(r2));
  if (pairwise_) reweigh_all();
  resum();
}

std::uint64_t DsmcEnsemble::random_draws() const {
  return events_.draws() + pairs_.draws() + sweep_.draws() + candidates_.draws() +
         partners_.draws();
}

// ---- Drag and shear (physics/flight/) ----

void DsmcEnsemble::set_flight_frame() {
  // Drag pulls every velocity towards 0 and shear turns it about 0, so the majorant is centred
  // there: |v_i - v_j| <= |v_i| + |v_j| holds whatever the centre, and a drift never carries a
  // speed about 0 beyond its growth factor. Shear flow is seen from the frame of the flow: the
  // velocities are centred (zero momentum, so that the mean stays 0 under the drift).
  if (flight_.shear != 0.0)
    for (auto& q : p_) q.v = q.v - v0_;
  set_shear_windows();
  v0_ = Vec3{};
}

void DsmcEnsemble::set_shear_windows() {
  // Only the no-splitting loop drifts between its events; the splitting schemes fly every
  // particle between collision steps, after which the strict majorant update is exact.
  if (flight_.shear == 0.0 || c_.scheme != Scheme::kNoSplit) return;
  window_ = flight::Shear::kWindow / std::abs(flight_.shear);
  if (gaussian_)  // the scale is folded at each window's end: cooling by at most e^-1 per window
    window_ = std::min(window_, 4.0 / (c_.kernel.area * c_.kernel.gamma * c_.kernel.C));
  growth_ = flight::Shear::growth(flight::Shear::kWindow);
  adapt_factor2_ *= growth_ * growth_;
}

void DsmcEnsemble::fly_all_to(double s) {
  Engine sweep = sweep_;
  const bool plane = c_.dimension == 2;
  for (auto& q : p_) {
    q.v = plane ? flight_.propagate<2>(q.v, s - q.t, sweep)
                : flight_.propagate<3>(q.v, s - q.t, sweep);
    q.t = s;
  }
  sweep_ = sweep;
  counts_.kicks += p_.size();
}

void DsmcEnsemble::start_window() {
  // Every particle is at the window's start: U = 2 g max |v| bounds every relative speed until
  // its end, and the collisions in it keep that bound (adapt_factor2_ holds g^2).
  double r2 = 0.0;
  for (const auto& q : p_) r2 = std::max(r2, norm2(q.v));
  set_majorant(2.0 * growth_ * std::sqrt(r2));
}

// ---- Global majorant (GRW05 §4, RW05 §3.4) ----

void DsmcEnsemble::set_majorant(double u_max) {
  u_max_ = u_max;
  u_max2_ = u_max * u_max;
  if (!pairwise_) inv_rate_ = 1.0 / c_.kernel.majorant_rate(static_cast<double>(p_.size()), u_max_);
}

GRANBOLTZ_HOT void DsmcEnsemble::adapt_majorant(const Particle& a) {
  // RW05 eq. (21) with the paper's factor 1, or the strict bound 2|v - V| >= |v - w|.
  const double r2 = adapt_factor2_ * norm2(a.v - v0_);
  if (r2 > u_max2_) set_majorant(std::sqrt(r2));
}

GRANBOLTZ_HOT void DsmcEnsemble::adapt_majorant_scaled(const Particle& a) {
  // Gaussian thermostat: the same rule for the true velocity V + s (w - V).
  const double r2 = adapt_factor2_ * gauss_.s2 * norm2(a.v - v0_);
  if (r2 > u_max2_) set_majorant(std::sqrt(r2));
}

void DsmcEnsemble::adapt_majorant_all() {
  if (c_.kernel.lambda == 0.0) return;  // U_max plays no role for Maxwell molecules
  if (pairwise_) return reweigh_all();
  for (const auto& q : p_) adapt_majorant(q);
}

// ---- Gaussian thermostat ----

void DsmcEnsemble::set_scale() {
  gauss_.s2 = gauss_.target / gauss_.energy;
  clock_ =
      pairwise_ ? inverse_power(lambda_case(c_.kernel.lambda), c_.kernel.lambda, gauss_.s2) : 1.0;
}

void DsmcEnsemble::fold_scale() {
  const auto folded = GaussianThermostat::fold(
      std::span<Particle>(p_.data(), p_.size()), {}, v0_,
      [&](double n) {
        return GaussianThermostat::target_of(c_.dimension, n, c_.initial_temperature);
      },
      [&](auto fn) {
        for (std::size_t i = 0; i < p_.size(); ++i) fn(i, 1.0, 0.0);
      });
  gauss_.energy = gauss_.target = folded.energy;
  set_scale();
  resum();
}

namespace {
// The terms of DsmcEnsemble::moment_sums() of one peculiar velocity c.
inline void moment_terms(const Vec3& c, double* q) {
  const double c2 = norm2(c);
  q[0] = c.x * c.x;
  q[1] = c.y * c.y;
  q[2] = c.z * c.z;
  q[3] = c.x * c.y;
  q[4] = c.x * c.z;
  q[5] = c.y * c.z;
  q[6] = c.x * c2;
  q[7] = c.y * c2;
  q[8] = c.z * c2;
}
}  // namespace

void DsmcEnsemble::set_tracking() {
  track_stress_ = lazy() && c_.correlations.stress.on;
  track_heat_ = lazy() && c_.correlations.heat_flux.on;
  track_ = track_stress_ || track_heat_;
}

void DsmcEnsemble::resum() {
  if (!track_) return;
  std::array<double, 9> sum{}, q;
  for (const auto& p : p_) {
    moment_terms(p.v - v0_, q.data());
    for (int k = 0; k < 9; ++k) sum[k] += q[k];
  }
  sums_ = sum;
}

GRANBOLTZ_HOT void DsmcEnsemble::track_pair(const Vec3& a0, const Vec3& b0, const Vec3& a1,
                                            const Vec3& b1) {
  // Equal masses keep P = a + b, so a pair's terms depend on P and g = a - b only:
  // a a + b b = (P P + g g)/2 and a|a|^2 + b|b|^2 = (P (|P|^2 + |g|^2) + 2 g (P.g))/4. The
  // change is then a third of the work of four particles' terms out and in.
  // Only the sums a correlation reads are kept between the folds.
  const Vec3 P = a0 + b0, g0 = a0 - b0, g1 = a1 - b1;
  if (track_stress_) {
    sums_[0] += 0.5 * (g1.x * g1.x - g0.x * g0.x);
    sums_[1] += 0.5 * (g1.y * g1.y - g0.y * g0.y);
    sums_[2] += 0.5 * (g1.z * g1.z - g0.z * g0.z);
    sums_[3] += 0.5 * (g1.x * g1.y - g0.x * g0.y);
    sums_[4] += 0.5 * (g1.x * g1.z - g0.x * g0.z);
    sums_[5] += 0.5 * (g1.y * g1.z - g0.y * g0.z);
  }
  if (!track_heat_) return;
  const double dA = norm2(g1) - norm2(g0), B0 = dot(P, g0), B1 = dot(P, g1);
  sums_[6] += 0.25 * (P.x * dA + 2.0 * (g1.x * B1 - g0.x * B0));
  sums_[7] += 0.25 * (P.y * dA + 2.0 * (g1.y * B1 - g0.y * B0));
  sums_[8] += 0.25 * (P.z * dA + 2.0 * (g1.z * B1 - g0.z * B0));
}

void DsmcEnsemble::rescale() {
  fold_scale();
  adapt_majorant_all();  // the global majorant is in true units already; the weights are not
}

template <int kLambda, bool kPairwise>
inline void DsmcEnsemble::after_gaussian_collision(double delta) {
  // The collision removed energy from the stored velocities; the scale grows so that the true
  // energy s^2 sum |w - V|^2 stays the target (the Gaussian thermostat, acting at once).
  gauss_.after_collision(delta);
  if constexpr (kPairwise) clock_ = inverse_power(kLambda, c_.kernel.lambda, gauss_.s2);
}

template <int kLambda>
GRANBOLTZ_HOT bool DsmcEnsemble::accept(double u2, Engine& events) {
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

// ---- Pairwise majorant: |u|^lambda <= (|v_i - V| + |v_j - V|)^lambda <= w_i + w_j ----

template <int kLambda>
GRANBOLTZ_HOT double DsmcEnsemble::weight(const Vec3& v) const {
  const double r2 = norm2(v - v0_);
  if constexpr (kLambda == kHardSpheres)
    return std::sqrt(r2);
  else if constexpr (kLambda == kHalf)
    return std::sqrt(std::sqrt(r2));
  else
    return std::pow(r2, 0.5 * c_.kernel.lambda);
}

template <int kLambda>
GRANBOLTZ_HOT void DsmcEnsemble::reweigh(std::uint32_t i) {
  const double w = weight<kLambda>(p_[i].v);
  w_sum_ += w - w_[i];
  w_[i] = w;
  if (w > w_max_) [[unlikely]]
    set_w_max(w);
}

void DsmcEnsemble::set_w_max(double w_max) {
  w_max_ = w_max;
  candidate_scale_ = 0x1p-32 * w_max;
}

template <int kLambda>
GRANBOLTZ_HOT void DsmcEnsemble::reweigh_pair(std::uint32_t i, std::uint32_t j) {
  reweigh<kLambda>(i);
  reweigh<kLambda>(j);
  // w_max only grows between sweeps, and the acceptance of a candidate is w_i / w_max: an exact
  // sweep every 2n pair updates (O(1) per event) keeps it near the current maximum, and the sum
  // exact.
  if (--refresh_countdown_ == 0)
    reweigh_all<kLambda>();
  else
    inv_rate_ = 1.0 / (pairwise_rate_factor_ * w_sum_);
}

template <int kLambda>
void DsmcEnsemble::reweigh_all() {
  // An exact sum at every sweep keeps the running sum from drifting.
  refresh_countdown_ = 2 * p_.size();
  double sum = 0.0, max = 0.0;
  for (std::size_t i = 0; i < p_.size(); ++i) {
    const double w = weight<kLambda>(p_[i].v);
    w_[i] = w;
    sum += w;
    max = std::max(max, w);
  }
  w_sum_ = sum;
  set_w_max(max);
  set_pairwise_rate();
}

void DsmcEnsemble::reweigh_all() {
  switch (lambda_case(c_.kernel.lambda)) {
    case kHardSpheres:
      return reweigh_all<kHardSpheres>();
    case kHalf:
      return reweigh_all<kHalf>();
    default:
      return reweigh_all<kGeneral>();
  }
}

void DsmcEnsemble::set_pairwise_rate() {
  // pi_hat = (1/2n) sum_{i != j} 4 pi gamma C (w_i + w_j) = 4 pi gamma C (n - 1) W / n (area
  // 2 pi for the 4 pi in d = 2).
  const double n = static_cast<double>(p_.size());
  pairwise_rate_factor_ = c_.kernel.area * c_.kernel.gamma * c_.kernel.C * (n - 1.0) / n;
  inv_rate_ = 1.0 / (pairwise_rate_factor_ * w_sum_);
}

template <int kLambda>
GRANBOLTZ_HOT bool DsmcEnsemble::accept_pairwise(double u2, double bound, std::uint32_t bits) {
  // Accept with probability |u|^lambda / (w_i + w_j), the weights being those the waiting time
  // was drawn with; 1 when a kick has carried |u|^lambda beyond them (the truncated kernel). The
  // uniform has 32 random bits: a bias below 2^-32 in the acceptance probability.
  const double r = (static_cast<double>(bits) + 0.5) * 0x1p-32 * bound;
  if constexpr (kLambda == kHardSpheres) {
    return r * r < u2;
  } else if constexpr (kLambda == kHalf) {
    return r * r * r * r < u2;
  } else {
    return r < std::pow(u2, 0.5 * c_.kernel.lambda);
  }
}

// ---- Candidate pairs ----

GRANBOLTZ_HOT DsmcEnsemble::Pair DsmcEnsemble::draw_pair(Engine& pairs) {
  const auto n = static_cast<std::uint32_t>(p_.size());
  Pair pair{0, 0, 0};
  // i uniform on {0..n-1}, j uniform on the others (GRW05 steps 2.3-2.4): the global majorant.
  uniform_index_pair(pairs, n, n - 1, pair.i, pair.j);
  if (pair.j >= pair.i) ++pair.j;
  return pair;
}

GRANBOLTZ_HOT DsmcEnsemble::Pair DsmcEnsemble::next_pair(Engine& pairs) {
  const Pair pair = ring_[head_];
  const Pair ahead = draw_pair(pairs);
  ring_[head_] = ahead;
  head_ = (head_ + 1) % kLookahead;
  __builtin_prefetch(&p_[ahead.i], 1);
  __builtin_prefetch(&p_[ahead.j], 1);
  return pair;
}

template <int kLambda, bool kPairwise>
GRANBOLTZ_HOT DsmcEnsemble::Pair DsmcEnsemble::select_pair(Engine& pairs) {
  if constexpr (!kPairwise) {
    return next_pair(pairs);
  } else {
    // The ordered pair (i, j) with probability proportional to w_i + w_j: i by weight (rejection
    // against w_max, with 32 acceptance bits: a bias below 2^-32 in the acceptance probability),
    // j uniform among the others; the order does not matter for a collision.
    const std::uint32_t i = candidates_.select(w_.data(), p_.data(), candidate_scale_);
    const IndexBits partner = partners_.next<true>(w_.data(), p_.data());
    return {i, partner.i + (partner.i >= i), partner.bits};
  }
}

// ---- Schemes ----

template <class Heat, int kLambda, bool kPairwise, class G>
bool DsmcEnsemble::run_nosplit(double s, const std::atomic<bool>* pause) {
  constexpr bool kHeated = Heat::kKicks, kGaussian = Heat::kLazyScale;
  const double alpha = c_.alpha;
  const WhiteNoiseThermostat noise{c_.beta};
  // Run-constant, so the branch below is always predicted: constant alpha keeps today's map.
  // The law is a local copy: particle stores cannot alias it, so it stays in registers.
  const bool constant_law = is_constant(c_.restitution);
  const RestitutionLaw law = c_.restitution;
  // Local copies of the streams: kept in registers instead of being stored after every draw.
  Engine ev = events_, pairs = pairs_;
  EventCounts counts = counts_;  // in registers during the loop
  std::uint64_t events = 0;
  bool reached = true;
  for (;;) {
    // A pause is taken between events, before the next waiting time is drawn.
    if (pause && (events & kPauseMask) == 0 && pause->load(std::memory_order_relaxed)) {
      reached = false;
      break;
    }
    double tau = exponential(ev) * inv_rate_;  // GRW05 step 2.1
    // Gaussian thermostat: a pairwise rate is in stored units, s^lambda times too small.
    if constexpr (kGaussian && kPairwise) tau *= clock_;
    if (t_ + tau >= s) break;
    t_ += tau;
    const Pair pair = select_pair<kLambda, kPairwise>(pairs);
    Particle& a = p_[pair.i];
    Particle& b = p_[pair.j];
    double bound = 0.0;
    if constexpr (kPairwise) bound = w_[pair.i] + w_[pair.j];
    if constexpr (kHeated) {  // step 2.5: kick both partners up to the event time
      if constexpr (std::is_same_v<Heat, LinearFlightKicks>) {
        a.v = flight_.template propagate<G::kDim>(a.v, t_ - a.t, ev);
        b.v = flight_.template propagate<G::kDim>(b.v, t_ - b.t, ev);
      } else {
        noise.template kick_pair<G::kDim>(a.v, t_ - a.t, b.v, t_ - b.t, ev);
      }
      a.t = t_;
      b.t = t_;
      counts.kicks += 2;
      if constexpr (kLambda != kMaxwell && !kPairwise) {  // step 2.7
        adapt_majorant(a);
        adapt_majorant(b);
      }
    }
    bool real = true;
    if constexpr (kPairwise)
      real = accept_pairwise<kLambda>(norm2(a.v - b.v), bound, pair.bits);
    else if constexpr (kGaussian && kLambda != kMaxwell)  // the global majorant is in true units
      real = accept<kLambda>(gauss_.s2 * norm2(a.v - b.v), ev);
    else if constexpr (kLambda != kMaxwell)
      real = accept<kLambda>(norm2(a.v - b.v), ev);  // 2.8
    if (real) {
      double before = 0.0;
      if constexpr (kGaussian) before = norm2(a.v - v0_) + norm2(b.v - v0_);
      const Vec3 a0 = a.v, b0 = b.v;
      if (constant_law) [[likely]]
        collide(a.v, b.v, G::direction(a.v - b.v, ev), alpha);  // step 2.9
      else  // eps(g_n) at the true normal speed: the stored one times s under the Gaussian
        collide_law(a.v, b.v, G::direction(a.v - b.v, ev), law, kGaussian ? gauss_.s2 : 1.0);
      if constexpr (!kHeated)
        if (track_) [[unlikely]]
          track_pair(a0 - v0_, b0 - v0_, a.v - v0_, b.v - v0_);
      if constexpr (kGaussian)
        after_gaussian_collision<kLambda, kPairwise>(norm2(a.v - v0_) + norm2(b.v - v0_) - before);
      ++counts.collisions;
    } else {
      ++counts.fictitious;
    }
    if constexpr (kPairwise) {
      if (real || kHeated) reweigh_pair<kLambda>(pair.i, pair.j);
    } else if constexpr (kLambda != kMaxwell) {
      if (real) {  // step 2.10
        if constexpr (kGaussian) {
          adapt_majorant_scaled(a);
          adapt_majorant_scaled(b);
        } else {
          adapt_majorant(a);
          adapt_majorant(b);
        }
      }
    }
    if constexpr (kGaussian)
      if (gauss_.s2 > kRefold) rescale();
    if ((++events & kProgressMask) == 0) report(t_);
  }
  events_ = ev;
  pairs_ = pairs;
  counts_ = counts;
  return reached;
}

void DsmcEnsemble::kick_all_to(double s) {
  if (linear_) {
    fly_all_to(s);
    adapt_majorant_all();
  } else if (heated_) {
    Engine sweep = sweep_;
    const std::size_t n = p_.size();
    const bool plane = c_.dimension == 2;
    for (std::size_t k = 0; k + 1 < n; k += 2) {
      if (plane)
        white_noise_kick2<2>(p_[k].v, s - p_[k].t, p_[k + 1].v, s - p_[k + 1].t, c_.beta, sweep);
      else
        white_noise_kick2(p_[k].v, s - p_[k].t, p_[k + 1].v, s - p_[k + 1].t, c_.beta, sweep);
      p_[k].t = p_[k + 1].t = s;
    }
    if (n % 2) {
      p_[n - 1].v = plane ? white_noise_kick_2d(p_[n - 1].v, c_.beta, s - p_[n - 1].t, sweep)
                          : white_noise_kick(p_[n - 1].v, c_.beta, s - p_[n - 1].t, sweep);
      p_[n - 1].t = s;
    }
    sweep_ = sweep;
    counts_.kicks += p_.size();
    adapt_majorant_all();
  } else {
    for (auto& q : p_) q.t = s;
  }
}

template <bool kGaussian, int kLambda, bool kPairwise, class G>
void DsmcEnsemble::collide_during(double h) {
  const double alpha = c_.alpha;
  const bool constant_law = is_constant(c_.restitution);
  const RestitutionLaw law = c_.restitution;
  Engine ev = events_, pairs = pairs_;
  EventCounts counts = counts_;
  double t = 0.0;
  std::uint64_t events = 0;
  for (;;) {
    if constexpr (kGaussian && kPairwise)
      t += exponential(ev) * inv_rate_ * clock_;
    else
      t += exponential(ev) * inv_rate_;
    if (t >= h) break;
    const Pair pair = select_pair<kLambda, kPairwise>(pairs);
    Particle& a = p_[pair.i];
    Particle& b = p_[pair.j];
    bool real = true;
    if constexpr (kPairwise)
      real = accept_pairwise<kLambda>(norm2(a.v - b.v), w_[pair.i] + w_[pair.j], pair.bits);
    else if constexpr (kGaussian && kLambda != kMaxwell)
      real = accept<kLambda>(gauss_.s2 * norm2(a.v - b.v), ev);
    else if constexpr (kLambda != kMaxwell)
      real = accept<kLambda>(norm2(a.v - b.v), ev);
    if (real) {
      double before = 0.0;
      if constexpr (kGaussian) before = norm2(a.v - v0_) + norm2(b.v - v0_);
      if (constant_law) [[likely]]
        collide(a.v, b.v, G::direction(a.v - b.v, ev), alpha);
      else
        collide_law(a.v, b.v, G::direction(a.v - b.v, ev), law, kGaussian ? gauss_.s2 : 1.0);
      if constexpr (kGaussian)
        after_gaussian_collision<kLambda, kPairwise>(norm2(a.v - v0_) + norm2(b.v - v0_) - before);
      ++counts.collisions;
      if constexpr (kPairwise) {
        reweigh_pair<kLambda>(pair.i, pair.j);
      } else if constexpr (kGaussian && kLambda != kMaxwell) {
        adapt_majorant_scaled(a);
        adapt_majorant_scaled(b);
      } else if constexpr (kLambda != kMaxwell) {
        adapt_majorant(a);
        adapt_majorant(b);
      }
      if constexpr (kGaussian)
        if (gauss_.s2 > kRefold) rescale();
    } else {
      ++counts.fictitious;
    }
    if ((++events & kProgressMask) == 0) report(t_ + t);
  }
  events_ = ev;
  pairs_ = pairs;
  counts_ = counts;
}

void DsmcEnsemble::kick_all_by(double h) {
  if (linear_) {
    // Drag or shear: the flight of every particle over the step. Under the Gaussian thermostat
    // (shear only, no noise) the flight is linear, so it commutes with the lazy scale, which is
    // folded after it: T is T0 again at the step's end.
    Engine sweep = sweep_;
    const bool plane = c_.dimension == 2;
    for (auto& q : p_)
      q.v = plane ? flight_.propagate<2>(q.v, h, sweep) : flight_.propagate<3>(q.v, h, sweep);
    sweep_ = sweep;
    counts_.kicks += p_.size();
    if (gaussian_)
      rescale();
    else
      adapt_majorant_all();
    return;
  }
  if (!heated_) return;
  // Blocks: first the normals (the ziggurat is scalar), then a branch-free update that the
  // compiler vectorises. Same numbers, in the same order, as kicking pair by pair.
  Engine sweep = sweep_;
  const std::size_t n = p_.size();
  const double sd = std::sqrt(2.0 * c_.beta * h);
  constexpr std::size_t kBlock = 256;  // particles per block (an even number)
  alignas(64) double z[3 * kBlock];
  if (c_.dimension == 2) {  // two normals per particle, z stays 0
    for (std::size_t start = 0; start < n; start += kBlock) {
      const std::size_t m = std::min(kBlock, n - start);
      for (std::size_t k = 0; k < m; ++k) normal_pair(sweep, z[2 * k], z[2 * k + 1]);
      Particle* q = p_.data() + start;
      for (std::size_t k = 0; k < m; ++k) {
        q[k].v.x += sd * z[2 * k];
        q[k].v.y += sd * z[2 * k + 1];
      }
    }
    sweep_ = sweep;
    counts_.kicks += p_.size();
    adapt_majorant_all();
    return;
  }
  for (std::size_t start = 0; start < n; start += kBlock) {
    const std::size_t m = std::min(kBlock, n - start);
    const std::size_t pairs = 3 * (m - m % 2) / 2;
    for (std::size_t k = 0; k < pairs; ++k) normal_pair(sweep, z[2 * k], z[2 * k + 1]);
    if (m % 2) {  // the last particle of an odd system: three normals of its own
      const Vec3 x = normal3(sweep);
      z[3 * m - 3] = x.x, z[3 * m - 2] = x.y, z[3 * m - 1] = x.z;
    }
    Particle* q = p_.data() + start;
    for (std::size_t k = 0; k < m; ++k) {
      q[k].v.x += sd * z[3 * k];
      q[k].v.y += sd * z[3 * k + 1];
      q[k].v.z += sd * z[3 * k + 2];
    }
  }
  sweep_ = sweep;
  counts_.kicks += p_.size();
  adapt_majorant_all();
}

namespace {
// Calls f.template operator()<kLambda, kPairwise, G>() for the runtime lambda case, majorant
// and geometry.
template <class G, class F>
void dispatch_kernel(int lc, bool pairwise, F&& f) {
  if (pairwise) {
    switch (lc) {
      case kHardSpheres:
        return f.template operator()<kHardSpheres, true, G>();
      case kHalf:
        return f.template operator()<kHalf, true, G>();
      default:
        return f.template operator()<kGeneral, true, G>();
    }
  }
  switch (lc) {
    case kMaxwell:
      return f.template operator()<kMaxwell, false, G>();
    case kHardSpheres:
      return f.template operator()<kHardSpheres, false, G>();
    case kHalf:
      return f.template operator()<kHalf, false, G>();
    default:
      return f.template operator()<kGeneral, false, G>();
  }
}

template <class F>
void dispatch(const DsmcConfig& c, int lc, bool pairwise, F&& f) {
  // In d = 3 both geometries are GRW05's uniform e (physics/geometry.hpp).
  if (c.dimension == 3) return dispatch_kernel<Sphere3>(lc, pairwise, f);
  if (c.geometry == Geometry::kImpact) return dispatch_kernel<CircleImpact>(lc, pairwise, f);
  return dispatch_kernel<CircleUniform>(lc, pairwise, f);
}
}  // namespace

bool DsmcEnsemble::run_events(double s, const std::atomic<bool>* pause) {
  // White noise with beta = 0 is free cooling: the loop without kicks.
  const Thermostat loop = heated_     ? Thermostat::kWhiteNoise
                          : gaussian_ ? Thermostat::kGaussian
                                      : Thermostat::kNone;
  bool reached = true;
  dispatch(c_, lambda_case(c_.kernel.lambda), pairwise_, [&]<int L, bool P, class G>() {
    ThermostatList::with(
        loop, [&](auto heat) { reached = run_nosplit<decltype(heat), L, P, G>(s, pause); });
  });
  return reached;
}

bool DsmcEnsemble::advance_events_to(double s, const std::atomic<bool>* pause) {
  // Nothing is pending at s but the kicks (none here) and the fold (the view's scale), so the
  // next events follow as if the loop had not stopped: the waiting time from s is memoryless.
  if (!run_events(s, pause)) return false;
  t_ = s;
  report(t_);
  return true;
}

bool DsmcEnsemble::advance_to(double s, const std::atomic<bool>* pause) {
  const int lc = lambda_case(c_.kernel.lambda);
  if (c_.scheme == Scheme::kNoSplit) {
    bool reached = true;
    if (linear_) {
      // Shear: windows of the majorant on the grid k * window_, each started with every
      // particle at its start (next_window_ is part of the state, so a pause or a checkpoint
      // continues the same windows).
      for (;;) {
        const bool windowed = window_ > 0.0;
        const double end = windowed ? static_cast<double>(next_window_) * window_ : s;
        const double until = std::min(end, s);
        dispatch(c_, lc, pairwise_, [&]<int L, bool P, class G>() {
          reached = run_nosplit<LinearFlightKicks, L, P, G>(until, pause);
        });
        if (!reached) return false;
        kick_all_to(until);
        t_ = until;
        if (!windowed || until < end) break;
        ++next_window_;
        if (gaussian_) fold_scale();
        start_window();
        if (until == s) break;
      }
    } else {
      if (!run_events(s, pause)) return false;
      kick_all_to(s);  // step 3.1 / Remark 2
    }
    t_ = s;
  } else {
    auto collide_for = [&](double h) {
      dispatch(c_, lc, pairwise_, [&]<int L, bool P, class G>() {
        if (gaussian_)
          collide_during<true, L, P, G>(h);
        else
          collide_during<false, L, P, G>(h);
      });
    };
    const double dt = c_.time_step();
    // Steps are counted from t = 0 so that t_k = k dt carries no accumulated round-off.
    auto k = static_cast<std::uint64_t>(std::llround(t_ / dt));
    const auto k_end = static_cast<std::uint64_t>(std::llround(s / dt));
    for (; k < k_end; ++k) {
      if (pause && pause->load(std::memory_order_relaxed)) return false;  // between steps
      if (c_.scheme == Scheme::kEuler) {                                  // RW05 Algorithm 1
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
  if (gaussian_)
    rescale();  // observers see the true velocities, at T = T0 exactly
  else
    resum();
  report(t_);
  return true;
}

// ---- Checkpoints ----

// The whole state, declared once for writing and reading (record/state_archive.hpp), in the
// layout of the checkpoints written so far.
void DsmcEnsemble::visit_state(StateArchive& a) {
  const std::size_t n = c_.particles;
  const bool plane = c_.dimension == 2;
  visit_particles(a, "particles", p_, nullptr, c_.dimension, counts_between(n, n));
  // Drag and shear centre the majorant on 0 (the flights contract or shear about it).
  const Real centre = zero_if(linear_, "under drag or shear");
  a.pack("scalars", real("t", t_, within(0.0, c_.t_end, "t_end")), real("V_x", v0_.x, centre),
         real("V_y", v0_.y, centre),
         real("V_z", v0_.z, linear_ ? centre : zero_if(plane, "in dimension 2")),
         real("u_max", u_max_, at_least(0.0)),
         real("w_sum", w_sum_, pairwise_ ? positive() : finite()), real("w_max", w_max_));
  a.each(
      "particles", n, 3, [&](std::size_t i) { return p_[i].t; }, within(0.0, t_, "t"));
  a.stream("events_stream", events_);
  a.stream("pairs_stream", pairs_);
  a.stream("sweep_stream", sweep_);
  a.table<std::uint64_t>(
      "ring_index", kLookahead, 2, {below(n, "n")},
      [&](std::size_t i, std::size_t k) -> std::uint64_t { return k ? ring_[i].j : ring_[i].i; },
      [&](std::size_t i, std::size_t k, std::uint64_t x) {
        (k ? ring_[i].j : ring_[i].i) = static_cast<std::uint32_t>(x);
        ring_[i].bits = 0;
      });
  a.pack("counters", word("head", head_, below(kLookahead, "the look-ahead")),
         word("collisions", counts_.collisions), word("fictitious", counts_.fictitious),
         word("kicks", counts_.kicks),
         word("sweep countdown", refresh_countdown_, up_to(2 * n, "2n")));
  if (pairwise_) {
    if (a.reading()) w_.assign(n, 0.0);
    a.table<double>(
        "weights", n, 0, {within(0.0, w_max_, "w_max")},
        [&](std::size_t i, std::size_t) { return w_[i]; },
        [&](std::size_t i, std::size_t, double x) { w_[i] = x; });
    visit_index_stream(a, "candidates", candidates_, static_cast<std::uint32_t>(n));
    visit_index_stream(a, "partners", partners_, static_cast<std::uint32_t>(n - 1));
  }
  if (gaussian_)  // the lazy scale: the particles above are the stored velocities w
    a.pack("thermostat", real("energy", gauss_.energy, positive()),
           real("target", gauss_.target, positive()));
  if (track_)  // the running sums as they are, round-off included, so a resumed run keeps its bits
    a.pack("moment_sums", real("cxx", sums_[0]), real("cyy", sums_[1]), real("czz", sums_[2]),
           real("cxy", sums_[3]), real("cxz", sums_[4]), real("cyz", sums_[5]),
           real("qx", sums_[6]), real("qy", sums_[7]), real("qz", sums_[8]));
  if (window_ > 0.0) {
    a.pack("flight_window", word("next window", next_window_, counts_between(1, UINT64_MAX)));
    a.require(
        "flight_window",
        [&] {
          return static_cast<double>(next_window_) * window_ > t_ &&
                 static_cast<double>(next_window_ - 1) * window_ <= t_;
        },
        "a shear window that does not hold the time");
  }
}

DsmcEnsemble::DsmcEnsemble(const DsmcConfig& config, const H5Reader& in, const std::string& g,
                           ProgressSlot* progress)
    : c_(config),
      p_(config.particles),
      adapt_factor2_(config.majorant_update == MajorantUpdate::kStrict ? 4.0 : 1.0),
      heated_(config.thermostat == Thermostat::kWhiteNoise && config.beta > 0.0),
      gaussian_(config.thermostat == Thermostat::kGaussian),
      pairwise_(config.majorant == MajorantKind::kPairwise),
      progress_(progress),
      flight_(config.flight_of(0)),
      linear_(config.linear_flight()) {
  if (linear_) set_shear_windows();  // the window and the majorant's growth factor, as constructed
  set_tracking();
  StateArchive r(in, g);
  visit_state(r);
  set_majorant(u_max_);
  if (pairwise_) {
    set_w_max(w_max_);
    set_pairwise_rate();
  }
  if (gaussian_) set_scale();
}

}  // namespace granboltz
