#pragma once
// One ensemble of the general homogeneous granular gas: K species of their own mass and diameter
// (a mixture), smooth or rough particles, in d = 2 or 3, with any restitution law and the three
// thermostats and time schemes of the one-species engine (dsmc/ensemble.hpp), which keeps the
// papers' gas. The particles of species a are the block [offset_a, offset_a + N_a).
//
// Majorant: one bound per pair of species (SPARTA's per-group-pair vremax): R_a >= |w_i - V0| for
// every stored velocity of species a, so |u| <= U_ab = R_a + R_b for any pair of classes (a, b);
// the class rate is (gamma/n) C sigma_ab^{d-1} |S^{d-1}| U_ab^lambda P_ab with P_ab the number of
// pairs. A class is drawn against the cumulative rates, the partners uniformly in their blocks,
// and the candidate is accepted with (|u|/U_ab)^lambda: exact, and efficient when the species'
// thermal speeds differ (masses tenfold apart).
//
// Free flight per species (dsmc.beta as a mapping, dsmc.drag): the particles of species a follow
// the exact law of flight_of(a) (physics/flight/; fly() in gas.cpp) on their translational
// velocities (spins are untouched), lazily from their own last time as the white-noise kicks. Drag
// pulls velocities towards 0, so the majorant is then centred at V0 = 0: without noise a speed
// about 0 only shrinks and the bounds stay exact; with noise the bounds follow the kicked partners
// (the truncated-kernel rule of white noise). A scalar beta without drag (or a mapping of equal
// values) keeps the white-noise kicks, draw for draw.
#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include "granboltz/dsmc/config.hpp"
#include "granboltz/dsmc/ensemble.hpp"
#include "granboltz/dsmc/particles.hpp"
#include "granboltz/exec/ensemble_pool.hpp"
#include "granboltz/h5/hdf5_io.hpp"
#include "granboltz/physics/pair_collision.hpp"
#include "granboltz/random/rng.hpp"
#include "granboltz/record/state_archive.hpp"

namespace granboltz {

class GasEnsemble {
 public:
  GasEnsemble(const DsmcConfig& config, std::uint64_t seed, std::uint64_t ensemble,
              ProgressSlot* progress = nullptr);
  /// Restores an ensemble saved by save().
  GasEnsemble(const DsmcConfig& config, const H5Reader& in, const std::string& group,
              ProgressSlot* progress = nullptr);

  /// As DsmcEnsemble::advance_to: on return every particle is kicked to s and, with the Gaussian
  /// thermostat, the scale is folded in, so particles() and spins() are the true values.
  bool advance_to(double s, const std::atomic<bool>* pause = nullptr);
  void save(H5Writer& out, const std::string& group) const { save_state(*this, out, group); }
  /// The state, declared once for save() and the restoring constructor: every dataset with its
  /// allowed values (record/state_archive.hpp).
  void visit_state(StateArchive& a);

  const Particles& particles() const { return p_; }
  /// Angular velocities (rough particles; d = 2: along z); empty for smooth ones.
  const std::vector<Vec3>& spins() const { return w_; }
  /// Replaces the velocities (empty: kept, clocks too) and, rough, the spins (empty: kept) at
  /// the current time, as DsmcEnsemble::set_velocities: clocks to time(), the centre of mass
  /// and the bounds R_a anew, the Gaussian thermostat rescales to its target energy.
  void set_state(const std::vector<Vec3>& v, const std::vector<Vec3>& spins);
  double time() const { return t_; }
  /// The largest pair bound U_ab (the one-species engine's U_max).
  double u_max() const;
  const EventCounts& counts() const { return counts_; }
  /// Real collisions a particle of species a took part in (a pair of one species counts twice).
  const std::vector<std::uint64_t>& species_collisions() const { return species_collisions_; }

 private:
  struct PairClass {
    std::uint32_t a, b;
    double pairs;      // P_ab
    double rate_unit;  // (gamma/n) C sigma_ab^{d-1} |S^{d-1}| P_ab
    double alpha;      // constant law: alpha_ab
    PairTerms terms;
  };
  void init_tables();
  void set_rates();                            // class rates and their sum from R_a
  void adapt(std::uint32_t a, const Vec3& v);  // R_a >= |v - V0|
  void adapt_all();
  double energy_of(std::uint32_t a, std::size_t i) const;  // m |w - V0|^2 + I |W|^2
  void fold();  // Gaussian: the scale into the stored values, exact energy
  template <class G, bool kFly>
  bool events(double s_end, const std::atomic<bool>* pause, bool kicks);
  void kick_all_to(double s);
  void kick_all_by(double h);
  void fly_all(double s, bool by);  // every particle's flight to s (by: over s from now)
  void report(double t) {
    if (progress_) progress_->store(t / c_.t_end, std::memory_order_relaxed);
  }

  const DsmcConfig& c_;
  Particles p_;
  std::vector<Vec3> w_;  // spins (rough)
  double t_ = 0.0;
  Vec3 v0_;  // centre-of-mass velocity at t = 0
  std::vector<PairClass> classes_;
  std::vector<double> mass_, inertia_, radius_;  // per species; inertia_ = I_a
  std::vector<double> r_max_;                    // R_a in stored units
  std::vector<double> cum_;                      // cumulative class rates (stored units)
  double rate_ = 0.0;                            // their sum
  bool heated_, gaussian_, rough_;
  bool flying_;                        // per-species beta or drag: the flights below
  std::vector<LinearFlight> flights_;  // flight_of(a) per species
  int lambda_case_ = 0;
  double s2_ = 1.0, energy_ = 0.0, target_ = 0.0;  // Gaussian: lazy scale, sum energy, its target
  Engine events_, pairs_, sweep_;
  EventCounts counts_;
  std::vector<std::uint64_t> species_collisions_;
  ProgressSlot* progress_;
};

}  // namespace granboltz
