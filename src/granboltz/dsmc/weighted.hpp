#pragma once
// The stochastic weighted particle method (SWPM; Rjasanow & Wagner, J. Comput. Phys. 124 (1996)
// 243, and their book, Springer 2005) for the heated inelastic Boltzmann equation, with the
// no-splitting time scheme of GRW05 §4 (per-particle kick times). Particles carry weights g_i
// (sum 1 = the density); the constant-weight engine (ensemble.hpp) is left untouched.
#include <atomic>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "granboltz/dsmc/config.hpp"
#include "granboltz/dsmc/ensemble.hpp"
#include "granboltz/dsmc/observables.hpp"
#include "granboltz/dsmc/particles.hpp"
#include "granboltz/physics/thermostat/gaussian.hpp"
#include "granboltz/random/rng.hpp"
#include "granboltz/record/state_archive.hpp"

namespace granboltz {

/// A complete binary sum tree over weights: the sum of the first k leaves by descent, an update
/// in O(log n). Internal nodes are recomputed from their children (never incremented), so the
/// sums do not drift however many updates there are.
class SumTree {
 public:
  void resize(std::size_t capacity);
  void set(std::size_t i, double g);
  double total() const { return node_.size() > 1 ? node_[1] : 0.0; }
  /// The leaf k with prefix(k) <= x < prefix(k + 1), for 0 <= x < total(); never a leaf of
  /// weight 0.
  std::size_t find(double x) const;

 private:
  std::size_t leaves_ = 0;
  std::vector<double> node_;  // node 1 the root, leaves at [leaves_, 2 leaves_)
};

/// The conserved moments of a weighted set of particles, about the origin: mass sum g,
/// momentum sum g v, energy sum g |v|^2 (for the tests and the reduction's checks).
struct WeightedMoments {
  double mass = 0.0;
  Vec3 momentum;
  double energy = 0.0;
};
WeightedMoments weighted_moments(std::span<const Particle> p, std::span<const double> g);

/// The central heat flux sum g (v - V) |v - V|^2 of a weighted set, V its mean velocity.
Vec3 weighted_heat_flux(std::span<const Particle> p, std::span<const double> g);

/// One weighted collision (GRW05 eq. 4 map with direction e): with gamma = min(g_a, g_b)/(1+kappa)
/// each partner keeps weight g - gamma at its velocity and two new particles of weight gamma sit
/// at the post-collision velocities. A partner whose weight reaches 0 is replaced by its new
/// particle (its slot is reused), otherwise the new particle is appended. Returns the number of
/// particles appended (0, 1 or 2). Conserves mass and momentum; the energy changes by
/// gamma * energy_change(v_a, v_b, e, alpha) (exactly 0 for alpha = 1), all to round-off.
/// `floor` > 0: weights stay >= floor; a pair whose gamma would be below it moves the whole lighter
/// weight (gamma = min(g_a, g_b)), and a remainder below it is dropped (the slot is replaced).
int weighted_collide(Particles& p, std::vector<double>& g, std::size_t a, std::size_t b, Vec3 e,
                     double alpha, double kappa, double t, double floor = 0.0);
/// The same with a restitution law eps(g_n) (restitution/collide.hpp): the constant law is the
/// call above with its alpha, bit for bit.
/// `s2`: the Gaussian thermostat's lazy scale squared, so that eps(g_n) sees the true normal speed
/// (the stored one times s); 1 without it.
int weighted_collide(Particles& p, std::vector<double>& g, std::size_t a, std::size_t b, Vec3 e,
                     const RestitutionLaw& law, double kappa, double t, double s2 = 1.0,
                     double floor = 0.0);

/// Replaces the group `members` (at least 3 particles) by two particles that keep its mass,
/// momentum and energy, and for kHeatFlux also its central heat flux, placed in the first two
/// member slots; the other members get weight 0 (the caller compacts). `e` is the direction
/// used when the heat flux is not kept or vanishes.
void merge_group(Particles& p, std::vector<double>& g, std::span<const std::uint32_t> members,
                 Reduction reduction, Vec3 e);

/// One step of the unbiased reduction on the d + 3 particles `step` (all kicked to one time):
/// their weights move along the direction that keeps sum g, sum g v and sum g |v|^2, to the first
/// zero weight on one side or the other, chosen so that the move is zero in expectation. Every
/// other sum g f(v) is kept in expectation; no velocity is created or changed. Returns the number
/// of weights set to 0 (1, or more on a tie; the caller compacts).
std::size_t thin_step(Particles& p, std::vector<double>& g, std::span<const std::uint32_t> step,
                      int dimension, Engine& eng);

/// Reduces the system to at most `target` particles by merging (kEnergy, kHeatFlux) or thinning
/// (kUnbiased) crowded groups: the particles are
/// binned on a cubic grid of width h sqrt(T) about the bulk velocity (h = 1/2, doubled until
/// enough particles can be merged) and the most crowded cells (at least 3 particles) are merged
/// first, so that sparse cells, the light tail particles among them, survive. Removes the
/// zero-weight slots. Deterministic given the particles and the engine.
void reduce_particles(Particles& p, std::vector<double>& g, std::size_t target, Reduction reduction,
                      Engine& eng, int dimension = 3);

/// What one split sweep did: particles added as copies, particles removed by roulette.
struct SplitCounts {
  std::uint64_t copies = 0;
  std::uint64_t removed = 0;
  std::uint64_t tail = 0;  ///< particles beyond the radius afterwards
};

/// The target weight of a particle at distance r from V (dsmc.weights.split):
/// w*(r) = g_ref (r/radius)^2 exp(-rate (r^power - radius^power)) beyond radius, g_ref within.
double split_target(const SplitSpec& s, double g_ref, double r);

/// One sweep of importance splitting and roulette on particles all kicked to one time, with the
/// targets beyond s.radius scaled by `scale` >= 1 (population control). A
/// particle beyond s.radius from V with g > 2 w*(r) becomes k = min(floor(g/w*), 16) copies of
/// equal weight (the same velocity; they part at their next kicks). Particles lighter than w*/4
/// are grouped by floor(ln(g_ref/w*)) (bands of a factor e in w*), and consecutive ones in a
/// band play pairwise roulette: one, chosen with probability proportional to its weight, takes
/// both weights. Splitting keeps every moment; roulette keeps the mass exactly and the other
/// moments in expectation. Zero-weight slots are removed.
SplitCounts split_particles(Particles& p, std::vector<double>& g, Vec3 V, const SplitSpec& s,
                            double g_ref, Engine& eng, double scale = 1.0);

class WeightedEnsemble {
 public:
  /// The initial Maxwellian with n = dsmc.particles particles of weight 1/n.
  WeightedEnsemble(const DsmcConfig& config, std::uint64_t seed, std::uint64_t ensemble,
                   ProgressSlot* progress = nullptr);
  /// Restores an ensemble saved by save().
  WeightedEnsemble(const DsmcConfig& config, const H5Reader& in, const std::string& group,
                   ProgressSlot* progress = nullptr);

  /// As DsmcEnsemble::advance_to: on return every particle is kicked up to s.
  bool advance_to(double s, const std::atomic<bool>* pause = nullptr);
  void save(H5Writer& out, const std::string& group) const { save_state(*this, out, group); }
  /// The state, declared once for save() and the restoring constructor: every dataset with its
  /// allowed values (record/state_archive.hpp).
  void visit_state(StateArchive& a);

  const Particles& particles() const { return p_; }
  const std::vector<double>& weights() const { return g_; }
  /// Replaces every velocity at the current time (weights kept), as
  /// DsmcEnsemble::set_velocities: clocks to time(), the weighted centre and the majorant anew.
  void set_velocities(const std::vector<Vec3>& v);
  double time() const { return t_; }
  /// The majorant in true units (with the Gaussian thermostat the stored bound times the scale).
  double u_max() const { return gaussian_ ? std::sqrt(gauss_.s2) * u_max_ : u_max_; }
  /// Gaussian thermostat: the integral of the cooling rate zeta = -d ln T/dt over [0, time()],
  /// ie. the sum over collisions of -ln(1 + delta E/E), E = sum g |v - V|^2 (0 otherwise).
  double cooling_integral() const { return cooled_ + (gaussian_ ? std::log(gauss_.s2) : 0.0); }
  /// Remembers the current time and cooling_integral() (the start of the steady window).
  void mark_cooling() { mark_cooled_ = cooling_integral(), mark_time_ = t_; }
  /// The mean cooling rate since the last mark_cooling() (or t = 0).
  double mean_cooling_rate() const {
    return t_ > mark_time_ ? (cooling_integral() - mark_cooled_) / (t_ - mark_time_) : 0.0;
  }
  const EventCounts& counts() const { return counts_; }
  std::uint64_t reductions() const { return reductions_; }
  std::uint64_t split_sweeps() const { return splits_; }

 private:
  template <class G>  // the collision geometry (physics/geometry.hpp), which fixes d
  bool advance_with(double s, const std::atomic<bool>* pause);
  void rebuild_tree();
  void adapt_majorant(const Vec3& v);
  void kick_all_to(double s);
  void reduce_to_cap();
  void split_sweep();
  void thin_dust();  // removes the particles lighter than their threshold (weighted.cpp)
  // Gaussian thermostat: the stored velocities w relate to the true ones by v = V + s (w - V),
  // V = v0_, s^2 = gauss_.s2, as in the constant-weight engine (the weighted collision map is
  // linear in the velocities, so it commutes with the scale; the weights do not see it).
  void fold_scale();          // v := V + f (w - m), f from the exact weighted sums: T = T0
  void recompute_majorant();  // u_max = 2 max |v - V|: strict, and free to shrink

  const DsmcConfig& c_;
  Particles p_;
  std::vector<double> g_;
  SumTree tree_;
  double t_ = 0.0;
  Vec3 v0_;
  double u_max_ = 0.0;
  double adapt_factor2_;
  bool heated_;
  bool gaussian_;             // dsmc.thermostat: gaussian
  double floor_;              // no weight is below it: kWeightFloor/n
  GaussianThermostat gauss_;  // energy = sum g |w - V|^2, kept current collision by collision
  double cooled_ = 0.0;       // sum of ln s^2 over the folds: the integral of zeta up to the last
  double mark_cooled_ = 0.0, mark_time_ = 0.0;  // cooling_integral() and t at mark_cooling()
  Engine events_, pairs_, sweep_, reduce_, split_;
  EventCounts counts_;
  std::uint64_t reductions_ = 0;
  std::uint64_t splits_ = 0;  // split sweeps done: the next is at (splits_ + 1) * interval
  double split_scale_ = 1.0;  // the tail's target weights are scaled by this (population control)
  ProgressSlot* progress_;
};

/// Weighted observers: as measure() and radial_histogram() with the empirical measure
/// sum_j g_j delta_{v_j}; o[0] is the density sum g (1 to round-off). The histogram adds the
/// weights per shell to `weight` and the particle numbers per shell to `count`.
Observation measure_weighted(std::span<const Particle> p, std::span<const double> g,
                             std::span<double> moments = {}, int dimension = 3);
void radial_histogram_weighted(std::span<const Particle> p, std::span<const double> g,
                               const HistogramSpec& spec, Vec3 V, double* weight,
                               std::uint64_t* count);
/// As component_histogram() with the weights: weight[k] += g_j, ++count[k].
void component_histogram_weighted(std::span<const Particle> p, std::span<const double> g,
                                  const HistogramSpec& spec, Vec3 V, double* weight,
                                  std::uint64_t* count);

}  // namespace granboltz
