#pragma once
// One ensemble of the DSMC particle system for the heated inelastic Boltzmann equation, advanced
// by one of the three time schemes of RW05: no-splitting (Algorithm 3 = GRW05 §4), Euler
// splitting (Algorithm 1), Strang splitting (Algorithm 2).
#include <atomic>
#include <cstdint>

#include "granboltz/dsmc_config.hpp"
#include "granboltz/ensemble_driver.hpp"
#include "granboltz/particles.hpp"
#include "granboltz/rng.hpp"

namespace granboltz {

/// Events of one ensemble (RW05 §4.2 effort model).
struct EventCounts {
  std::uint64_t collisions = 0;  ///< real collisions
  std::uint64_t fictitious = 0;  ///< rejected candidate pairs
  std::uint64_t kicks = 0;       ///< single-particle kicks (white-noise updates)
};

class DsmcEnsemble {
 public:
  /// Draws the initial Maxwellian and the majorant (GRW05 steps 1.1-1.4).
  /// `progress`, if given, receives the fraction of [0, t_end] simulated so far.
  DsmcEnsemble(const DsmcConfig& config, std::uint64_t seed, std::uint64_t ensemble,
               ProgressSlot* progress = nullptr);

  /// Advances the system to time s > time(); on return every particle is kicked up to s
  /// (GRW05 Remark 2), ready to be observed. For the splitting schemes s must lie on the grid
  /// of time steps.
  void advance_to(double s);

  const Particles& particles() const { return p_; }
  double time() const { return t_; }
  double u_max() const { return u_max_; }
  const EventCounts& counts() const { return counts_; }
  /// Raw 64-bit random numbers drawn since construction by the event loop and the kicks
  /// (not the initial condition): the work floor that no implementation can go below.
  std::uint64_t random_draws() const;

 private:
  void advance_nosplit(double s);
  void collide_during(double h);   // collision step of length h (splitting schemes)
  void kick_all_by(double h);      // kicking step of length h (splitting schemes)
  void kick_all_to(double s);      // kick every particle from its own last time to s
  void kick(Particle& p, double t);
  bool try_collide(Particle& a, Particle& b);
  void adapt_majorant(const Particle& a);
  void adapt_majorant_all();
  void update_rate();
  void report(double t) {
    if (progress_) progress_->store(t / c_.t_end, std::memory_order_relaxed);
  }

  const DsmcConfig& c_;
  Particles p_;
  double t_ = 0.0;
  Vec3 v0_;              // bulk velocity at t = 0: the centre of the majorant (GRW05 step 1.3)
  double u_max_ = 0.0;   // U_max
  double rate_ = 0.0;    // pi_hat = 2 pi gamma C (n - 1) U_max^lambda
  bool heated_;          // beta > 0
  bool track_majorant_;  // lambda > 0: U_max matters
  Engine events_, pairs_, sweep_;
  EventCounts counts_;
  ProgressSlot* progress_;
};

}  // namespace granboltz
