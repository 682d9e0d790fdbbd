#include "granboltz/dsmc/engine.hpp"

#include <stdexcept>

#include "granboltz/dsmc/gas.hpp"
#include "granboltz/dsmc/gas_observables.hpp"
#include "granboltz/dsmc/initial_from.hpp"
#include "granboltz/dsmc/weighted.hpp"
#include "granboltz/random/rng.hpp"

namespace granboltz {

void Ensemble::set_spins(const std::vector<Vec3>&) {
  throw std::logic_error(std::string("set_spins: the ") + engine() +
                         " engine has no spins (only rough particles, dsmc.roughness, have them)");
}

std::vector<double> Ensemble::event_columns() const {
  const EventCounts& c = counts();
  return {static_cast<double>(c.collisions), static_cast<double>(c.fictitious),
          static_cast<double>(c.kicks), u_max()};
}

namespace {

// Each engine wrapped as it is: the wrapper forwards, it never copies particles, and its one
// virtual call per advance_to is all the boundary costs. The engine is a member (constructed in
// place), so the wrapper adds no allocation of its own.

class PapersGas final : public Ensemble {
 public:
  template <class... Args>
  explicit PapersGas(const DsmcConfig& d, Args&&... args)
      : e_(d, std::forward<Args>(args)...), block_{0, e_.particles().size()} {}
  const char* engine() const override { return "dsmc"; }
  bool advance_to(double s, const std::atomic<bool>* pause) override {
    return e_.advance_to(s, pause);
  }
  double time() const override { return e_.time(); }
  ParticleView view() const override { return {e_.particles(), {}, {}, {&block_, 1}}; }
  bool advance_lazily(double s, const std::atomic<bool>* pause) override {
    return e_.lazy() ? e_.advance_events_to(s, pause) : e_.advance_to(s, pause);
  }
  ParticleView lazy_view() const override {
    if (!e_.lazy()) return view();
    bulk_ = e_.centre();
    return {e_.particles(), {}, {}, {&block_, 1}, &bulk_, e_.scale(), e_.moment_sums()};
  }
  void save(H5Writer& out, const std::string& group) const override { e_.save(out, group); }
  void set_velocities(const std::vector<Vec3>& v) override { e_.set_velocities(v); }
  Observation observe(const DsmcConfig& d, const RowTargets& out) const override {
    return measure(e_.particles(), out.moments, d.dimension);
  }
  const EventCounts& counts() const override { return e_.counts(); }
  double u_max() const override { return e_.u_max(); }

 private:
  DsmcEnsemble e_;
  SpeciesBlock block_;
  mutable Vec3 bulk_;
};

class GeneralGas final : public Ensemble {
 public:
  template <class... Args>
  explicit GeneralGas(const DsmcConfig& d, Args&&... args)
      : e_(d, std::forward<Args>(args)...), species_written_(d.species_written) {
    for (const SpeciesSpec& sp : d.species) blocks_.push_back({sp.offset, sp.count});
  }
  const char* engine() const override { return "gas"; }
  bool advance_to(double s, const std::atomic<bool>* pause) override {
    return e_.advance_to(s, pause);
  }
  double time() const override { return e_.time(); }
  ParticleView view() const override { return {e_.particles(), e_.spins(), {}, blocks_}; }
  void save(H5Writer& out, const std::string& group) const override { e_.save(out, group); }
  void set_velocities(const std::vector<Vec3>& v) override { e_.set_state(v, {}); }
  void set_spins(const std::vector<Vec3>& spins) override {
    if (e_.spins().empty()) Ensemble::set_spins(spins);  // smooth particles of a mixture
    e_.set_state({}, spins);
  }
  Observation observe(const DsmcConfig& d, const RowTargets& out) const override {
    return measure_gas(d, e_.particles(), e_.spins(), out.moments, out.rows, out.row_moments);
  }
  const EventCounts& counts() const override { return e_.counts(); }
  double u_max() const override { return e_.u_max(); }
  std::vector<double> event_columns() const override {
    std::vector<double> c = Ensemble::event_columns();
    if (species_written_)
      for (const std::uint64_t k : e_.species_collisions()) c.push_back(static_cast<double>(k));
    return c;
  }

 private:
  GasEnsemble e_;
  bool species_written_;
  std::vector<SpeciesBlock> blocks_;
};

class Weighted final : public Ensemble {
 public:
  template <class... Args>
  explicit Weighted(const DsmcConfig& d, Args&&... args)
      : e_(d, std::forward<Args>(args)...), gaussian_(d.thermostat == Thermostat::kGaussian) {}
  const char* engine() const override { return "weighted"; }
  bool weighted() const override { return true; }
  bool advance_to(double s, const std::atomic<bool>* pause) override {
    return e_.advance_to(s, pause);
  }
  double time() const override { return e_.time(); }
  ParticleView view() const override {
    block_ = {0, e_.particles().size()};  // the particle number changes as the run goes
    return {e_.particles(), {}, e_.weights(), {&block_, 1}};
  }
  void save(H5Writer& out, const std::string& group) const override { e_.save(out, group); }
  void set_velocities(const std::vector<Vec3>& v) override { e_.set_velocities(v); }
  Observation observe(const DsmcConfig& d, const RowTargets& out) const override {
    return measure_weighted(e_.particles(), e_.weights(), out.moments, d.dimension);
  }
  void mark_window() override { e_.mark_cooling(); }
  const EventCounts& counts() const override { return e_.counts(); }
  double u_max() const override { return e_.u_max(); }
  std::vector<double> event_columns() const override {
    std::vector<double> c = Ensemble::event_columns();
    c.push_back(static_cast<double>(e_.reductions()));
    c.push_back(static_cast<double>(e_.particles().size()));
    if (gaussian_) c.push_back(e_.mean_cooling_rate());
    return c;
  }
  std::vector<std::pair<std::string, std::uint64_t>> extra_counts() const override {
    return {{"reductions", e_.reductions()}, {"split_sweeps", e_.split_sweeps()}};
  }
  double mean_cooling_rate() const override { return e_.mean_cooling_rate(); }

 private:
  WeightedEnsemble e_;
  bool gaussian_;
  mutable SpeciesBlock block_;
};

// The one choice among the engines, for a new ensemble and a restored one alike.
template <class... Args>
std::unique_ptr<Ensemble> make(const DsmcConfig& d, Args&&... args) {
  if (d.weights.swpm) return std::make_unique<Weighted>(d, std::forward<Args>(args)...);
  if (d.general()) return std::make_unique<GeneralGas>(d, std::forward<Args>(args)...);
  return std::make_unique<PapersGas>(d, std::forward<Args>(args)...);
}

}  // namespace

std::unique_ptr<Ensemble> make_ensemble(const DsmcConfig& config, std::uint64_t seed,
                                        std::uint64_t ensemble, ProgressSlot* progress) {
  std::unique_ptr<Ensemble> e =
      make(config, config.source ? continued_seed(seed, config.initial_from_hash) : seed, ensemble,
           progress);
  if (config.source) {  // dsmc.initial.from: the source's final state replaces the drawn start
    const SourceState s = source_state(config, ensemble);
    e->set_velocities(s.velocities);
    if (config.roughness.on) e->set_spins(s.spins);
  }
  return e;
}

std::unique_ptr<Ensemble> restore_ensemble(const DsmcConfig& config, const H5Reader& in,
                                           const std::string& group, ProgressSlot* progress) {
  return make(config, in, group, progress);
}

}  // namespace granboltz
