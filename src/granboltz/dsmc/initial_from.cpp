#include "granboltz/dsmc/initial_from.hpp"

#include <stdexcept>
#include <type_traits>

#include "granboltz/dsmc/ensemble.hpp"
#include "granboltz/dsmc/gas.hpp"

namespace granboltz {

namespace {
// The engine of `d` for (seed, ensemble), started from its own source if it has one.
template <class Engine>
void start_from_source(const DsmcConfig& d, std::uint64_t ensemble, Engine& engine);
}  // namespace

SourceState source_state(const DsmcConfig& d, std::uint64_t ensemble) {
  const SourceRun& src = *d.source;
  if (ensemble >= src.ensembles)
    throw std::invalid_argument("dsmc.initial.from: ensemble " + std::to_string(ensemble) +
                                " is beyond the source's " + std::to_string(src.ensembles));
  SourceState out;
  if (src.dsmc.general()) {
    GasEnsemble engine(src.dsmc, src.seed, ensemble);
    start_from_source(src.dsmc, ensemble, engine);
    engine.advance_to(src.dsmc.t_end);
    for (const auto& q : engine.particles()) out.velocities.push_back(q.v);
    out.spins = engine.spins();
  } else {
    DsmcEnsemble engine(src.dsmc, src.seed, ensemble);
    start_from_source(src.dsmc, ensemble, engine);
    engine.advance_to(src.dsmc.t_end);
    for (const auto& q : engine.particles()) out.velocities.push_back(q.v);
  }
  return out;
}

namespace {
template <class Engine>
void start_from_source(const DsmcConfig& d, std::uint64_t ensemble, Engine& engine) {
  if (!d.source) return;
  const SourceState s = source_state(d, ensemble);
  if constexpr (std::is_same_v<Engine, GasEnsemble>)
    engine.set_state(s.velocities, d.roughness.on ? s.spins : std::vector<Vec3>{});
  else
    engine.set_velocities(s.velocities);
}
}  // namespace

void apply_source(const DsmcConfig& d, std::uint64_t ensemble, DsmcEnsemble& engine) {
  start_from_source(d, ensemble, engine);
}

void apply_source(const DsmcConfig& d, std::uint64_t ensemble, GasEnsemble& engine) {
  start_from_source(d, ensemble, engine);
}

}  // namespace granboltz
