#include "granboltz/dsmc/observers/cooling_rate.hpp"

#include "granboltz/stats/statistics.hpp"

namespace granboltz {

void CoolingRateObserver::declare(Record& record, LayoutPhase phase) const {
  // Right after the weighted engine's column /events/cooling_rate, where it has always been.
  if (phase == LayoutPhase::kCoolingRate) record.declare_moments("cooling_rate", 1);
}

void CoolingRateObserver::accumulate(const FinishedEnsemble& f, const ObserverRows&,
                                     Record& record) const {
  record.moments("cooling_rate")[0].add(f.ensemble.mean_cooling_rate());
}

void CoolingRateObserver::present(Presenter& out, const Record& record) const {
  const std::string g = d_.steady ? "/steady/cooling_rate" : "/cooling_rate";
  const std::string description =
      "zeta = -d ln T/dt: the rate at which inelastic collisions remove the energy E = sum g "
      "|v - V|^2 that the Gaussian thermostat restores, (energy lost per unit time)/E, averaged "
      "over (steady_from, t_end] in each ensemble; mean and ci over the ensembles";
  const MeanCi z = record.moments("cooling_rate")[0].stats(record.ensembles());
  out.write(g + "/mean", std::vector<double>{z.mean}, {}, description + ": mean");
  out.write(g + "/ci", std::vector<double>{z.ci}, {}, description + ": confidence half-width");
  out.write(g + "/variance", std::vector<double>{z.variance}, {},
            description + ": variance over the ensembles");
  out.attr(g, "description", description);
}

}  // namespace granboltz
