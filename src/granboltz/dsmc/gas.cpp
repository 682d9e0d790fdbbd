#include "granboltz/dsmc/gas.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "granboltz/core/hot.hpp"
#include "granboltz/dsmc/initial_state.hpp"
#include "granboltz/dsmc/particles_io.hpp"
#include "granboltz/physics/geometry.hpp"
#include "granboltz/physics/heating.hpp"
#include "granboltz/physics/restitution/laws.hpp"
#include "granboltz/random/samplers.hpp"

namespace granboltz {

namespace {
constexpr std::uint64_t kProgressMask = (1u << 20) - 1;
constexpr std::uint64_t kPauseMask = (1u << 14) - 1;
// Gaussian thermostat: fold the scale in once the stored energy has fallen by 2^8 (as the
// one-species engine does, for the same reason: the running energy keeps its digits).
constexpr double kRefold = 0x1p8;
constexpr int kMaxwell = 0, kHardSpheres = 1, kHalf = 2, kGeneral = 3;

template <class E>
Vec3 normals(int d, E& eng) {
  if (d == 2) {
    const double a = normal(eng);
    const double b = normal(eng);
    return {a, b, 0.0};
  }
  return normal3(eng);
}

// White noise over a time s (physics/heating.hpp): translational velocities only. Flattened: the
// normal sampler inlined, which GCC's heuristics stopped doing once the flights below were in
// this file (7 % of the heated mixture's time).
template <class E>
[[gnu::flatten]] Vec3 kick(int d, Vec3 v, double beta, double s, E& eng) {
  return d == 2 ? white_noise_kick_2d(v, beta, s, eng) : white_noise_kick(v, beta, s, eng);
}

// The per-species flights run where they differ from the white-noise kicks: drag, or beta per
// species of unequal values (equal values are the scalar key: same kicks, same bits).
bool flies(const DsmcConfig& c) {
  if (c.linear_flight()) return true;
  for (double b : c.beta_species)
    if (b != c.beta) return true;
  return false;
}

// One particle's flight over s, exact: the law of its species' LinearFlight::propagate, drawn in
// closed form because the general gas has no shear (a drag run 1.6x faster than with the general
// propagator, whose covariance series is for the sheared case). White noise alone is the
// white-noise kick; drag alone (A = gamma I) the Ornstein-Uhlenbeck step, mean e^{-gamma s} v and
// variance per component beta (1 - e^{-2 gamma s}) / gamma.
Vec3 fly(const LinearFlight& f, int d, Vec3 v, double s, Engine& eng) {
  if (f.gamma == 0.0) return f.beta > 0.0 ? kick(d, v, f.beta, s, eng) : v;
  const Vec3 m = std::exp(-f.gamma * s) * v;
  if (f.beta == 0.0 || s <= 0.0) return m;
  return m + std::sqrt(-f.beta * std::expm1(-2.0 * f.gamma * s) / f.gamma) * normals(d, eng);
}

// d_rot: the rotational degrees of freedom of a rough particle.
int rotational_dof(int d) { return d == 2 ? 1 : 3; }
}  // namespace

void GasEnsemble::init_tables() {
  const std::size_t K = c_.species.size();
  const double n = static_cast<double>(c_.particles);
  for (const auto& sp : c_.species) {
    mass_.push_back(sp.mass);
    radius_.push_back(0.5 * sp.diameter);
    inertia_.push_back(sp.moment_of_inertia());
  }
  const double lambda = c_.kernel.lambda;
  lambda_case_ = lambda == 0.0   ? kMaxwell
                 : lambda == 1.0 ? kHardSpheres
                 : lambda == 0.5 ? kHalf
                                 : kGeneral;
  for (std::uint32_t a = 0; a < K; ++a)
    for (std::uint32_t b = a; b < K; ++b) {
      const auto Na = static_cast<double>(c_.species[a].count);
      const auto Nb = static_cast<double>(c_.species[b].count);
      PairClass pc{};
      pc.a = a;
      pc.b = b;
      pc.pairs = a == b ? 0.5 * Na * (Na - 1.0) : Na * Nb;
      const double sigma = 0.5 * (c_.species[a].diameter + c_.species[b].diameter);
      const double cross = c_.dimension == 2 ? sigma : sigma * sigma;  // sigma_ab^{d-1}
      pc.rate_unit = c_.kernel.gamma / n * c_.kernel.C * cross * c_.kernel.area * pc.pairs;
      pc.alpha = c_.pair_alpha(a, b);
      pc.terms = pair_terms(mass_[a], mass_[b], c_.species[a].diameter, c_.species[b].diameter,
                            rough_ ? c_.roughness.beta : -1.0, rough_ ? c_.species[a].inertia : 0.0,
                            rough_ ? c_.species[b].inertia : 0.0);
      classes_.push_back(pc);
    }
  for (std::size_t a = 0; a < K; ++a) {
    flights_.push_back(c_.flight_of(a));
    // The config refuses dsmc.shear here; fly() has no sheared case.
    if (flights_.back().shear != 0.0)
      throw std::logic_error("GasEnsemble: shear flow not supported");
  }
  r_max_.assign(K, 0.0);
  cum_.assign(classes_.size(), 0.0);
  species_collisions_.assign(K, 0);
}

GasEnsemble::GasEnsemble(const DsmcConfig& config, std::uint64_t seed, std::uint64_t ensemble,
                         ProgressSlot* progress)
    : c_(config),
      p_(config.particles),
      heated_(config.thermostat == Thermostat::kWhiteNoise && config.beta > 0.0),
      gaussian_(config.thermostat == Thermostat::kGaussian),
      rough_(config.roughness.on),
      flying_(flies(config)),
      events_(make_stream(seed, ensemble, Consumer::kEvents)),
      pairs_(make_stream(seed, ensemble, Consumer::kPairs)),
      sweep_(make_stream(seed, ensemble, Consumer::kSweep)),
      progress_(progress) {
  init_tables();
  // Every species Maxwellian at T0: velocity variance T0/m_a per component.
  Engine init = make_stream(seed, ensemble, Consumer::kInitial);
  Vec3 momentum;
  double total_mass = 0.0;
  // A prepared start per species: an anisotropic Maxwellian of covariance T / m_a, or a skewed
  // state in which every species has the heat flux q of its velocities scaled by sqrt(m_a) (the
  // output's convention), the same reduced state x = v / sqrt(T0/m_a).
  const PreparedStart start = prepared_start(c_.initial_temperature_tensor, c_.initial_heat_flux,
                                             c_.dimension, c_.initial_temperature);
  for (std::size_t a = 0; a < c_.species.size(); ++a) {
    const double sd = std::sqrt(c_.initial_temperature / mass_[a]);
    const auto& sp = c_.species[a];
    for (std::uint64_t i = sp.offset; i < sp.offset + sp.count; ++i) {
      if (const auto v = start.velocity(mass_[a], init))
        p_[i].v = *v;
      else
        p_[i].v = sd * normals(c_.dimension, init);
      p_[i].t = 0.0;
      momentum += mass_[a] * p_[i].v;
      total_mass += mass_[a];
    }
  }
  v0_ = (1.0 / total_mass) * momentum;
  if (c_.linear_flight()) v0_ = Vec3{};  // drag pulls towards 0: the majorant's centre
  if (rough_) {
    w_.resize(p_.size());
    Engine spin = make_stream(seed, ensemble, Consumer::kInitialSpin);
    for (std::size_t a = 0; a < c_.species.size(); ++a) {
      const double sd = std::sqrt(c_.initial_rotational_temperature / inertia_[a]);
      const auto& sp = c_.species[a];
      for (std::uint64_t i = sp.offset; i < sp.offset + sp.count; ++i)
        w_[i] = c_.dimension == 2 ? Vec3{0.0, 0.0, sd * normal(spin)} : sd * normal3(spin);
    }
  }
  if (gaussian_) {
    // The thermostat keeps the total energy, translational and rotational, at its expected
    // initial value: n (d T0 + d_rot T_rot(0)).
    const double n = static_cast<double>(p_.size());
    target_ =
        n * (c_.dimension * c_.initial_temperature +
             (rough_ ? rotational_dof(c_.dimension) * c_.initial_rotational_temperature : 0.0));
    fold();
  }
  adapt_all();
}

void GasEnsemble::set_state(const std::vector<Vec3>& v, const std::vector<Vec3>& spins) {
  if (!v.empty()) {
    Vec3 momentum;
    double total_mass = 0.0;
    for (std::size_t a = 0; a < c_.species.size(); ++a) {
      const auto& sp = c_.species[a];
      for (std::uint64_t i = sp.offset; i < sp.offset + sp.count; ++i) {
        p_[i].v = v[i];
        p_[i].t = t_;
        momentum += mass_[a] * v[i];
        total_mass += mass_[a];
      }
    }
    v0_ = c_.linear_flight() ? Vec3{} : (1.0 / total_mass) * momentum;
  }
  if (rough_ && !spins.empty()) w_ = spins;
  if (gaussian_) fold();
  adapt_all();
}

double GasEnsemble::energy_of(std::uint32_t a, std::size_t i) const {
  double e = mass_[a] * norm2(p_[i].v - v0_);
  if (rough_) e += inertia_[a] * norm2(w_[i]);
  return e;
}

void GasEnsemble::set_rates() {
  double sum = 0.0;
  for (std::size_t k = 0; k < classes_.size(); ++k) {
    const PairClass& pc = classes_[k];
    const double U = r_max_[pc.a] + r_max_[pc.b];
    double power = 1.0;
    switch (lambda_case_) {
      case kMaxwell:
        break;
      case kHardSpheres:
        power = U;
        break;
      case kHalf:
        power = std::sqrt(U);
        break;
      default:
        power = std::pow(U, c_.kernel.lambda);
    }
    sum += pc.rate_unit * power;
    cum_[k] = sum;
  }
  rate_ = sum;
}

GRANBOLTZ_HOT void GasEnsemble::adapt(std::uint32_t a, const Vec3& v) {
  const double r2 = norm2(v - v0_);
  if (r2 > r_max_[a] * r_max_[a]) {
    r_max_[a] = std::sqrt(r2);
    set_rates();
  }
}

void GasEnsemble::adapt_all() {
  // The exact maxima of the current state: a valid bound from now on (it may also shrink, which
  // keeps a cooling gas efficient).
  for (std::size_t a = 0; a < c_.species.size(); ++a) {
    const auto& sp = c_.species[a];
    double r2 = 0.0;
    for (std::uint64_t i = sp.offset; i < sp.offset + sp.count; ++i)
      r2 = std::max(r2, norm2(p_[i].v - v0_));
    r_max_[a] = std::sqrt(r2);
  }
  set_rates();
}

void GasEnsemble::fold() {
  // Masses weigh the centre and the energy: the total energy, spins included, is the target.
  const auto folded = GaussianThermostat::fold(
      std::span<Particle>(p_.data(), p_.size()),
      rough_ ? std::span<Vec3>(w_.data(), w_.size()) : std::span<Vec3>{}, v0_,
      [&](double) { return target_; },
      [&](auto fn) {
        for (std::size_t a = 0; a < c_.species.size(); ++a) {
          const auto& sp = c_.species[a];
          for (std::uint64_t i = sp.offset; i < sp.offset + sp.count; ++i)
            fn(i, mass_[a], inertia_[a]);
        }
      });
  energy_ = folded.energy;
  s2_ = target_ / energy_;
  // The bounds were in the old stored units.
  for (double& r : r_max_) r *= folded.factor;
  set_rates();
}

double GasEnsemble::u_max() const {
  double u = 0.0;
  for (const auto& pc : classes_) u = std::max(u, r_max_[pc.a] + r_max_[pc.b]);
  return u * std::sqrt(s2_);
}

template <class G, bool kFly>
bool GasEnsemble::events(double s_end, const std::atomic<bool>* pause, bool kicks) {
  const bool constant_law = is_constant(c_.restitution);
  const RestitutionLaw law = c_.restitution;
  const double beta = c_.beta, lambda = c_.kernel.lambda;
  const int lc = lambda_case_;
  Engine ev = events_, pairs = pairs_;
  EventCounts counts = counts_;
  std::uint64_t events = 0;
  bool reached = true;
  // s^lambda: the true rate over the stored one (Gaussian thermostat; else 1).
  auto rate_scale = [&] {
    if (!gaussian_ || lc == kMaxwell) return 1.0;
    if (lc == kHardSpheres) return std::sqrt(s2_);
    return std::pow(s2_, 0.5 * lambda);
  };
  double scale = rate_scale();
  for (;;) {
    if (pause && (events & kPauseMask) == 0 && pause->load(std::memory_order_relaxed)) {
      reached = false;
      break;
    }
    const double tau = exponential(ev) / (rate_ * scale);
    if (t_ + tau >= s_end) break;
    t_ += tau;
    // The class against the cumulative rates, then the partners uniformly in their blocks.
    const double x = uniform01(ev) * rate_;
    std::size_t k = 0;
    while (k + 1 < classes_.size() && !(x < cum_[k])) ++k;
    const PairClass& pc = classes_[k];
    const SpeciesSpec& sa = c_.species[pc.a];
    const SpeciesSpec& sb = c_.species[pc.b];
    std::uint64_t i, j;
    if (pc.a == pc.b) {
      const std::uint64_t i0 = uniform_index(pairs, sa.count);
      const std::uint64_t j0 = uniform_index(pairs, sa.count - 1);
      i = sa.offset + i0;
      j = sa.offset + j0 + (j0 >= i0);
    } else {
      i = sa.offset + uniform_index(pairs, sa.count);
      j = sb.offset + uniform_index(pairs, sb.count);
    }
    Particle& A = p_[i];
    Particle& B = p_[j];
    if (kicks) {             // the free flight of the translational velocities up to the event time
      if constexpr (kFly) {  // per species: white noise, drag
        A.v = fly(flights_[pc.a], G::kDim, A.v, t_ - A.t, ev);
        B.v = fly(flights_[pc.b], G::kDim, B.v, t_ - B.t, ev);
      } else {
        A.v = kick(c_.dimension, A.v, beta, t_ - A.t, ev);
        B.v = kick(c_.dimension, B.v, beta, t_ - B.t, ev);
      }
      A.t = B.t = t_;
      counts.kicks += 2;
      adapt(pc.a, A.v);
      adapt(pc.b, B.v);
    }
    bool real = true;
    if (lc != kMaxwell) {
      const double U = r_max_[pc.a] + r_max_[pc.b];
      const double u2 = norm2(A.v - B.v);
      const double r = uniform01(ev);
      if (lc == kHardSpheres)
        real = r * r * (U * U) < u2;
      else if (lc == kHalf)
        real = (r * r) * (r * r) * (U * U) < u2;
      else
        real = r < std::pow(u2 / (U * U), 0.5 * lambda);
    }
    if (!real) {
      ++counts.fictitious;
    } else {
      const Vec3 u = A.v - B.v;
      const Vec3 e = G::direction(u, ev);
      Vec3 n;
      if (impact_normal(u, e, n)) {
        double eps = pc.alpha;
        if (!constant_law) {
          const double gn = dot(u, n);
          eps = std::visit(
              [&](const auto& l) {
                using Law = std::decay_t<decltype(l)>;
                return l.eps_of_g2(Law::kScaleFree ? gn * gn : gn * gn * s2_);
              },
              law);
        }
        double before = 0.0;
        if (gaussian_) before = energy_of(pc.a, i) + energy_of(pc.b, j);
        if (rough_)
          collide_rough(A.v, w_[i], B.v, w_[j], n, eps, pc.terms);
        else
          collide_smooth(A.v, B.v, n, eps, pc.terms);
        if (gaussian_) {
          energy_ += energy_of(pc.a, i) + energy_of(pc.b, j) - before;
          s2_ = target_ / energy_;
        }
      }
      ++counts.collisions;
      ++species_collisions_[pc.a];
      ++species_collisions_[pc.b];
      if (lc != kMaxwell) {
        adapt(pc.a, A.v);
        adapt(pc.b, B.v);
      }
      if (gaussian_) {
        if (s2_ > kRefold) fold();
        scale = rate_scale();
      }
    }
    if ((++events & kProgressMask) == 0) report(t_);
  }
  events_ = ev;
  pairs_ = pairs;
  counts_ = counts;
  return reached;
}

void GasEnsemble::fly_all(double s, bool by) {
  // Species by species, particles in order, one stream: the same draws at any thread count.
  Engine sweep = sweep_;
  for (std::size_t a = 0; a < c_.species.size(); ++a) {
    const LinearFlight& f = flights_[a];
    const auto& sp = c_.species[a];
    for (std::uint64_t i = sp.offset; i < sp.offset + sp.count; ++i) {
      Particle& q = p_[i];
      const double h = by ? s : s - q.t;
      q.v = fly(f, c_.dimension, q.v, h, sweep);
      if (!by) q.t = s;
    }
  }
  sweep_ = sweep;
  counts_.kicks += p_.size();
}

[[gnu::flatten]] void GasEnsemble::kick_all_to(double s) {  // flattened as kick_all_by below
  if (flying_) {
    fly_all(s, false);
  } else if (heated_) {
    for (auto& q : p_) {
      q.v = kick(c_.dimension, q.v, c_.beta, s - q.t, sweep_);
      q.t = s;
    }
    counts_.kicks += p_.size();
  } else {
    for (auto& q : p_) q.t = s;
  }
}

// Flattened as kick() above: the normal sampler inlined into the white-noise sweep.
[[gnu::flatten]] void GasEnsemble::kick_all_by(double h) {
  if (flying_) {
    fly_all(h, true);
    adapt_all();
    return;
  }
  if (!heated_) return;
  const double sd = std::sqrt(2.0 * c_.beta * h);
  for (auto& q : p_) q.v += sd * normals(c_.dimension, sweep_);
  counts_.kicks += p_.size();
  adapt_all();
}

bool GasEnsemble::advance_to(double s, const std::atomic<bool>* pause) {
  auto run = [&](double until, const std::atomic<bool>* p, bool kicks) {
    if (flying_) {
      if (c_.dimension == 3) return events<Sphere3, true>(until, p, kicks);
      if (c_.geometry == Geometry::kImpact) return events<CircleImpact, true>(until, p, kicks);
      return events<CircleUniform, true>(until, p, kicks);
    }
    if (c_.dimension == 3) return events<Sphere3, false>(until, p, kicks);
    if (c_.geometry == Geometry::kImpact) return events<CircleImpact, false>(until, p, kicks);
    return events<CircleUniform, false>(until, p, kicks);
  };
  if (c_.scheme == Scheme::kNoSplit) {
    if (!run(s, pause, heated_ || flying_)) return false;
    kick_all_to(s);
    t_ = s;
  } else {
    const double dt = c_.time_step();
    auto k = static_cast<std::uint64_t>(std::llround(t_ / dt));
    const auto k_end = static_cast<std::uint64_t>(std::llround(s / dt));
    auto collide_for = [&](double start, double h) {
      t_ = start;
      run(start + h, nullptr, false);
    };
    for (; k < k_end; ++k) {
      if (pause && pause->load(std::memory_order_relaxed)) return false;
      const double t0 = static_cast<double>(k) * dt;
      if (c_.scheme == Scheme::kEuler) {
        collide_for(t0, dt);
        kick_all_by(dt);
      } else {
        collide_for(t0, 0.5 * dt);
        kick_all_by(dt);
        collide_for(t0 + 0.5 * dt, 0.5 * dt);
      }
      t_ = static_cast<double>(k + 1) * dt;
      report(t_);
    }
    t_ = s;
  }
  if (gaussian_) fold();
  adapt_all();
  report(t_);
  return true;
}

// ---- Checkpoints ----

// The whole state, declared once for writing and reading (record/state_archive.hpp), in the
// layout of the checkpoints written so far.
void GasEnsemble::visit_state(StateArchive& a) {
  const std::size_t n = c_.particles, K = c_.species.size();
  const bool plane = c_.dimension == 2;
  visit_particles(a, "particles", p_, nullptr, c_.dimension, counts_between(n, n));
  if (rough_) {
    if (a.reading()) w_.resize(n);
    const Real in_plane = zero_if(plane, "in dimension 2");  // a spin on the z axis
    a.table<double>(
        "spins", n, 3, {in_plane, in_plane, finite()},
        [&](std::size_t i, std::size_t k) { return k == 0   ? w_[i].x
                                                   : k == 1 ? w_[i].y
                                                            : w_[i].z; },
        [&](std::size_t i, std::size_t k, double x) {
          (k == 0 ? w_[i].x : k == 1 ? w_[i].y : w_[i].z) = x;
        });
  }
  // Drag and shear centre the majorant on 0 (the flights contract or shear about it).
  const Real centre = zero_if(c_.linear_flight(), "under drag or shear");
  const Real energy = gaussian_ ? positive() : finite();
  a.pack("scalars", real("t", t_, within(0.0, c_.t_end, "t_end")), real("V_x", v0_.x, centre),
         real("V_y", v0_.y, centre),
         real("V_z", v0_.z, c_.linear_flight() ? centre : zero_if(plane, "in dimension 2")),
         real("energy", energy_, energy), real("target", target_, energy));
  a.each(
      "particles", n, 3, [&](std::size_t i) { return p_[i].t; }, within(0.0, t_, "t"));
  if (a.reading()) r_max_.resize(K), species_collisions_.resize(K);
  a.table<double>(
      "bounds", K, 0, {at_least(0.0)}, [&](std::size_t i, std::size_t) { return r_max_[i]; },
      [&](std::size_t i, std::size_t, double x) { r_max_[i] = x; });
  a.stream("events_stream", events_);
  a.stream("pairs_stream", pairs_);
  a.stream("sweep_stream", sweep_);
  a.pack("counters", word("collisions", counts_.collisions), word("fictitious", counts_.fictitious),
         word("kicks", counts_.kicks));
  a.table<std::uint64_t>(
      "species_collisions", K, 0, {Count{}},
      [&](std::size_t i, std::size_t) { return species_collisions_[i]; },
      [&](std::size_t i, std::size_t, std::uint64_t x) { species_collisions_[i] = x; });
  // A bound below a particle's speed would make a probability exceed 1.
  a.require(
      "particles",
      [&] {
        for (std::size_t s = 0; s < K; ++s)
          for (std::uint64_t i = c_.species[s].offset;
               i < c_.species[s].offset + c_.species[s].count; ++i)
            if (norm(p_[i].v - v0_) > r_max_[s] * (1.0 + 1e-12)) return false;
        return true;
      },
      "a velocity beyond its species' bound (bounds)");
}

GasEnsemble::GasEnsemble(const DsmcConfig& config, const H5Reader& in, const std::string& g,
                         ProgressSlot* progress)
    : c_(config),
      p_(config.particles),
      heated_(config.thermostat == Thermostat::kWhiteNoise && config.beta > 0.0),
      gaussian_(config.thermostat == Thermostat::kGaussian),
      rough_(config.roughness.on),
      flying_(flies(config)),
      progress_(progress) {
  init_tables();
  StateArchive r(in, g);
  visit_state(r);
  if (gaussian_) s2_ = target_ / energy_;
  set_rates();
}

}  // namespace granboltz
