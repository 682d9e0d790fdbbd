#pragma once
// The engine boundary: what every caller (the run driver, the Python Simulation, the estimate's
// pilot) sees of one ensemble, whichever of the three engines advances it — the papers' gas
// (DsmcEnsemble, dsmc/ensemble.hpp), the general gas of mixtures and rough particles
// (GasEnsemble, dsmc/gas.hpp), weighted particles (WeightedEnsemble, dsmc/weighted.hpp).
// make_ensemble() and restore_ensemble() are the only places that choose among them. The
// engines themselves are untouched: each is wrapped (dsmc/engine.cpp), and a call crosses the
// boundary once per advance_to, never per event, so the tuned loops keep their bits and speed.
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "granboltz/dsmc/config.hpp"
#include "granboltz/dsmc/ensemble.hpp"  // EventCounts
#include "granboltz/dsmc/observables.hpp"
#include "granboltz/dsmc/particles.hpp"
#include "granboltz/exec/ensemble_pool.hpp"
#include "granboltz/h5/hdf5_io.hpp"

namespace granboltz {

/// The particles of species a: [offset, offset + count) of the particle array.
struct SpeciesBlock {
  std::size_t offset = 0, count = 0;
};

/// A view of the particles at the engine's time (valid until the next call that changes it).
struct ParticleView {
  std::span<const Particle> particles;
  std::span<const Vec3> spins;            ///< rough particles: one per particle; empty otherwise
  std::span<const double> weights;        ///< weighted particles: one per particle; empty otherwise
  std::span<const SpeciesBlock> species;  ///< one block per species (one for a single species)
  /// A lazy view (Ensemble::advance_lazily): the true velocity of a stored w is
  /// bulk + scale (w - bulk), bulk the gas's conserved mean velocity; null for a view whose
  /// particles hold their true velocities (the mean then has to be summed).
  const Vec3* bulk = nullptr;
  double scale = 1.0;
  /// A lazy view may hold the engine's running sums over c = w - bulk of c_x^2, c_y^2, c_z^2,
  /// c_x c_y, c_x c_z, c_y c_z, c |c|^2 (DsmcEnsemble::moment_sums): null when it has none.
  const double* sums = nullptr;
};

/// Where one observation row goes (the run driver's per-ensemble rows; the Python observe()
/// passes only `moments` and `rows`): null pointers and empty spans are not filled.
struct RowTargets {
  std::span<double> moments;               ///< <|v - V|^{2p}>, p = 1..dsmc.moments
  std::vector<double*> rows, row_moments;  ///< the rows of extra_row_sets() (general gas)
};

/// One ensemble of a DSMC run, made by make_ensemble() or restore_ensemble().
class Ensemble {
 public:
  virtual ~Ensemble() = default;
  Ensemble() = default;
  Ensemble(const Ensemble&) = delete;
  Ensemble& operator=(const Ensemble&) = delete;

  /// "dsmc", "gas" or "weighted": the engine behind (Simulation.engine).
  virtual const char* engine() const = 0;
  /// Particles carry weights (view().weights): the histograms then have weights per shell too.
  virtual bool weighted() const { return false; }

  /// Advances to s > time(); on return every particle is kicked to s and the Gaussian scale is
  /// folded in, so that view() holds the true state. Returns false early, at a point from which a
  /// later call continues exactly, if `pause` becomes true (DsmcEnsemble::advance_to).
  virtual bool advance_to(double s, const std::atomic<bool>* pause = nullptr) = 0;
  virtual double time() const = 0;
  virtual ParticleView view() const = 0;
  /// Advances to s > time() for a sample between the rows without perturbing the run: where
  /// the engine can read its state at s in place (the papers' gas, no-splitting scheme, Gaussian
  /// thermostat or none: no particle has a kick pending), the event loop only stops at s, and
  /// lazy_view() maps the stored velocities to the true ones. Elsewhere (white-noise kicks are
  /// random, so a lazy particle's state at s is not yet drawn; splitting schemes; flights;
  /// the other engines) it is advance_to and lazy_view() is view().
  virtual bool advance_lazily(double s, const std::atomic<bool>* pause = nullptr) {
    return advance_to(s, pause);
  }
  virtual ParticleView lazy_view() const { return view(); }

  /// The complete state under `group` (restore_ensemble reads it back).
  virtual void save(H5Writer& out, const std::string& group) const = 0;
  /// Replaces every velocity at time() (the caller checks count and finiteness), as
  /// DsmcEnsemble::set_velocities.
  virtual void set_velocities(const std::vector<Vec3>& v) = 0;
  /// Rough particles: replaces every spin at time(); refused (std::logic_error) by the others.
  virtual void set_spins(const std::vector<Vec3>& spins);

  /// The observables of the current state into one row: the scalars returned, the rest into
  /// `out`, each engine with its own observers (dsmc/observables.hpp, gas_observables.hpp, the
  /// weighted ones of weighted.hpp), on the particles in place.
  virtual Observation observe(const DsmcConfig& d, const RowTargets& out) const = 0;
  /// Remembers now as the start of the window of the engine's own time averages (the weighted
  /// engine's cooling rate under the Gaussian thermostat; nothing for the others).
  virtual void mark_window() {}

  virtual const EventCounts& counts() const = 0;
  /// The majorant's bound U_max in true units (the largest pair bound for the general gas).
  virtual double u_max() const = 0;
  /// The run's columns of /events for this ensemble, in the order dsmc_layout declares them:
  /// collisions, fictitious, kicks, u_max_final, then the engine's own (the weighted engine's
  /// reductions, final particle number and, Gaussian, mean cooling rate; the mixture's
  /// collisions per species).
  virtual std::vector<double> event_columns() const;
  /// Counts beyond counts() with their names (the weighted engine's reductions and split
  /// sweeps), for Simulation.counts.
  virtual std::vector<std::pair<std::string, std::uint64_t>> extra_counts() const { return {}; }
  /// Weighted, Gaussian thermostat: the mean cooling rate since mark_window(); 0 otherwise.
  virtual double mean_cooling_rate() const { return 0.0; }
};

/// The engine a config asks for: weighted particles (dsmc.weights: swpm), else the general gas
/// (species or roughness written: DsmcConfig::general), else the papers' one-species engine.
/// `config` must outlive the ensemble (the engines keep a reference to it).
std::unique_ptr<Ensemble> make_ensemble(const DsmcConfig& config, std::uint64_t seed,
                                        std::uint64_t ensemble, ProgressSlot* progress = nullptr);
/// The same engine, restored from save()'s `group` of `in`.
std::unique_ptr<Ensemble> restore_ensemble(const DsmcConfig& config, const H5Reader& in,
                                           const std::string& group,
                                           ProgressSlot* progress = nullptr);

}  // namespace granboltz
