#pragma once
// The cost of a run before it starts: expected events, peak memory and wall time on this machine.
//
// Events come from the rates the engines use. DSMC (RW05 §4.2 effort model): real collisions at
// the rate 2 pi gamma C (n-1) E|u|^lambda of a Maxwellian whose temperature follows the
// moment equation dT/dt = 2 beta - (pi gamma C (1 - alpha^2)(n-1)/6n) E|u|^(2+lambda) (T = T0
// under the Gaussian thermostat); candidates at the majorant rate 2 pi gamma C (n-1) U_max^lambda
// (U_max from the extreme value of the velocities the update sees) or 4 pi gamma C (n-1)
// E|v-V|^lambda (pairwise); kicks 2 per candidate plus n per observation (no-splitting) or n per
// time step (splitting). The ODE is integrated until its fixed point, then with steps growing
// with t: O(log t_end) steps, bounded. The general gas (mixtures, rough particles): the moment
// equations of every species' translational and rotational temperatures (the Maxwellian
// approximation, the exact energy exchange of the collision map), with the per-species bounds
// the engine resets at observations. TV06: the collisions are the config's (warm-up
// included); the fictitious candidates from omega_max against <phi(v1)> for the DSMC intruder,
// and for the needle's thinning from a pilot ensemble of at most 20 000 collisions. Wall time:
// events at per-candidate, per-collision and per-kick costs measured with make bench, plus
// splitting steps, kicks, observations and every sum and count of the output's record at
// measured costs. Weighted particles (SWPM): events and time from a pilot, ensemble 0 of the
// run up to 10^5 candidates in a child process given 1 s, extrapolated to t_end (its CPU time is
// measured, so this part of the estimate is of this machine as it runs). The stated accuracy
// (events within 10-15 %, time within a factor 2 on an idle machine) and its tests:
// docs/output.md. A cost without a bound (not finite, particles the engine cannot represent,
// more events per ensemble than 2^63, a TV06 run of more than 2^63 samples) throws ConfigError
// naming the key.
#include <cstdint>
#include <string>

#include "granboltz/app/config.hpp"

namespace granboltz {

struct RunEstimate {
  std::uint64_t ensembles = 0;  ///< of this shard
  double collisions = 0.0;      ///< real collisions, all ensembles, warm-up included
  double fictitious = 0.0;      ///< rejected candidates
  double kicks = 0.0;           ///< single-particle white-noise updates (DSMC)
  std::uint64_t memory_bytes = 0;
  unsigned threads = 1;
  double seconds = 0.0;  ///< wall time on `threads` threads of this machine
  /// SWPM only: the pilot did not pass its first stop in its second, so `seconds` is a lower
  /// bound and the events are those of constant weights.
  bool lower_bound = false;
};

/// The estimate of a run of `config` on `threads` worker threads (0: all cores). Throws
/// ConfigError if it is not finite.
RunEstimate estimate_run(const Config& config, unsigned threads);

/// Throws ConfigError, naming the key to blame, if the cost of a run of `config` cannot be
/// bounded: an estimate that is not finite, particles the engine cannot represent, or more
/// events per ensemble than its counters hold. The closed forms only (no pilot): well under a
/// millisecond for most configs, so every run checks it, quiet or not.
void check_cost_bounded(const Config& config);

/// One line: "7 ensembles: 1.23e+07 collisions, 4.1e+06 fictitious, 2.5e+07 kicks; peak memory
/// 70.0 MiB; wall time about 1.2 min on 2 threads".
std::string describe(const RunEstimate& e);

/// A byte count for people: "70.0 MiB".
std::string human_bytes(double bytes);

}  // namespace granboltz
