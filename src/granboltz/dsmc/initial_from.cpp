#include "granboltz/dsmc/initial_from.hpp"

#include <stdexcept>
#include <string>

#include "granboltz/dsmc/engine.hpp"
#include "granboltz/dsmc/run.hpp"

namespace granboltz {

SourceState source_state(const DsmcConfig& d, std::uint64_t ensemble) {
  const SourceRun& src = *d.source;
  if (ensemble >= src.ensembles)
    throw std::invalid_argument("dsmc.initial.from: ensemble " + std::to_string(ensemble) +
                                " is beyond the source's " + std::to_string(src.ensembles));
  // make_ensemble starts it from its own source, if it has one. The run stopped at each of its
  // observation times (every particle kicked there), so the replay stops at the same times.
  const std::unique_ptr<Ensemble> engine = make_ensemble(src.dsmc, src.seed, ensemble);
  // A source with time correlations also stopped at their samples.
  for (const double t : dsmc_times(src.dsmc)) {
    for (double s = src.dsmc.correlations.next_after(engine->time(), src.dsmc.t_end); s <= t;
         s = src.dsmc.correlations.next_after(s, src.dsmc.t_end))
      engine->advance_to(s);
    if (t > engine->time()) engine->advance_to(t);
  }
  const ParticleView view = engine->view();
  SourceState out;
  out.velocities.reserve(view.particles.size());
  for (const Particle& q : view.particles) out.velocities.push_back(q.v);
  out.spins.assign(view.spins.begin(), view.spins.end());
  return out;
}

}  // namespace granboltz
