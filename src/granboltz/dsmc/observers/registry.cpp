#include "granboltz/dsmc/observers/registry.hpp"

#include "granboltz/dsmc/observers/cooling_rate.hpp"
#include "granboltz/dsmc/observers/correlations.hpp"
#include "granboltz/dsmc/observers/histogram.hpp"
#include "granboltz/dsmc/observers/moments.hpp"
#include "granboltz/dsmc/observers/ratios.hpp"
#include "granboltz/dsmc/observers/rotation.hpp"
#include "granboltz/dsmc/observers/species.hpp"

namespace granboltz {

std::vector<std::unique_ptr<Observer>> make_observers(const DsmcConfig& d) {
  std::vector<std::unique_ptr<Observer>> out;
  // One line per observer: whether the config asks for it, and the observer. The order is that
  // of the output's datasets (and of the manifest); the record's layout is set by LayoutPhase.
  out.push_back(std::make_unique<MomentsObserver>(d));
  if (d.histogram.shells)
    out.push_back(std::make_unique<HistogramObserver>(d, HistogramObserver::kRadial));
  if (d.weights.swpm && d.thermostat == Thermostat::kGaussian)
    out.push_back(std::make_unique<CoolingRateObserver>(d));
  if (d.histogram.shells && d.histogram.component)
    out.push_back(std::make_unique<HistogramObserver>(d, HistogramObserver::kComponent));
  // The general gas: the species' rows, then T_rot, in the engine's order (extra_row_sets).
  const SpeciesObserver* species = nullptr;
  std::size_t species_at = RatiosObserver::kNone, rotation_at = RatiosObserver::kNone;
  if (d.species_written) {
    species_at = out.size();
    species =
        static_cast<SpeciesObserver*>(out.emplace_back(std::make_unique<SpeciesObserver>(d)).get());
  }
  if (d.roughness.on) {
    rotation_at = out.size();
    out.push_back(std::make_unique<RotationObserver>(d));
  }
  if (!ratio_sets(d).empty())
    out.push_back(std::make_unique<RatiosObserver>(d, 0, species, species_at, rotation_at));
  if (d.correlations.any()) out.push_back(std::make_unique<CorrelationsObserver>(d));
  return out;
}

}  // namespace granboltz
