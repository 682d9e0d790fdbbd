#pragma once
// TV06 §3.1 and §4: the 1-D intruder of mass M in a thermalized bath, by the Gillespie algorithm
// and by DSMC. The physics kernels (collision rule, one Gillespie event) are small inline
// functions; the event loops run one ensemble and return its time averages.
#include <cstdint>

#include "granboltz/exec/ensemble_pool.hpp"
#include "granboltz/tv06/bath.hpp"
#include "granboltz/tv06/config.hpp"
#include "granboltz/tv06/observe.hpp"

namespace granboltz::tv06 {

/// TV06 eq. 17 (pdf text; eq. 21 of the html text): the intruder's velocity after a collision
/// with a bath particle of velocity v (bath mass 1, restitution alpha). At M = alpha it is v.
inline double intruder_velocity_after(double v1, double v, double mass, double alpha) {
  return v1 + (1.0 + alpha) / (1.0 + mass) * (v - v1);
}

/// One Gillespie event for an intruder moving at v1.
struct IntruderCollision {
  double wait = 0.0;           ///< time to the collision, eq. 10
  Side side = Side::kPlus;     ///< eq. 11
  double bath_velocity = 0.0;  ///< from g_+ or g_-, eqs. 12-13 (exactly, not on a window)
};

/// Steps 1, 3 and 4 of TV06's pseudocode. The rates are constant between collisions (eq. 4),
/// so the waiting time is exponential with rate phi(v1).
template <IntruderBath B, class E>
IntruderCollision next_collision(const B& bath, double v1, E& eng) {
  const Fluxes f = bath.fluxes(v1);
  const double total = f.total();
  IntruderCollision c;
  c.wait = exponential(eng) / total;
  c.side = uniform01(eng) * total < f.plus ? Side::kPlus : Side::kMinus;
  c.bath_velocity = bath.sample_colliding(eng, v1, c.side);
  return c;
}

/// The time averages and counts of one ensemble of an intruder run.
struct IntruderEnsemble {
  double temperature_ratio = 0.0;       ///< T/T_B = M <v1^2> / T_B over the samples
  double mean_velocity = 0.0;           ///< <v1> (0 in the stationary state)
  std::uint64_t samples = 0;            ///< sample times after the warm-up
  std::uint64_t collisions = 0;         ///< real collisions after the warm-up
  std::uint64_t fictitious = 0;         ///< DSMC: rejected candidates (wrong side or thinned)
  std::uint64_t majorant_exceeded = 0;  ///< DSMC: candidates with omega_i1 > omega_max
  double time = 0.0;                    ///< simulated time after the warm-up
  double omega_max = 0.0;               ///< DSMC: the majorant at the end
  std::uint64_t draws = 0;              ///< raw random numbers drawn (benchmark floor)
  Histogram histogram;                  ///< of v1 at the sample times
};

/// The bath of an intruder config (TV06 eqs. 14 and 19).
double intruder_bath_temperature(const IntruderConfig& c);
/// The sampling interval: `sample_every`, or the mean free time 1/phi(0) when it is 0.
double intruder_sample_interval(const IntruderConfig& c);
/// T/T_B when it is known exactly: Gaussian bath, (1+alpha)/(2+(1-alpha)/M) (Martin and
/// Piasecki, TV06 eq. 18); any bath at M = alpha: alpha. Returns false otherwise.
bool intruder_exact_temperature_ratio(const IntruderConfig& c, double* ratio);

/// Runs ensemble `ensemble` of an intruder config (either method); v1 starts at 0.
IntruderEnsemble simulate_intruder(const IntruderConfig& c, std::uint64_t seed,
                                   std::uint64_t ensemble, ProgressSlot* slot = nullptr);

}  // namespace granboltz::tv06
