#pragma once
// The cooling rate of weighted particles under the Gaussian thermostat: zeta = -d ln T/dt of the
// collisions alone, which the thermostat undoes. The engine integrates it over the steady window
// (Ensemble::mean_cooling_rate); this observer sums each ensemble's mean and presents its mean and
// interval over the ensembles at /steady/cooling_rate (or /cooling_rate without steady_from).
#include "granboltz/dsmc/observers/observer.hpp"

namespace granboltz {

class CoolingRateObserver final : public Observer {
 public:
  explicit CoolingRateObserver(const DsmcConfig& d) : d_(d) {}

  const char* name() const override { return "cooling_rate"; }
  void declare(Record& record, LayoutPhase phase) const override;
  void accumulate(const FinishedEnsemble& ensemble, const ObserverRows& rows,
                  Record& record) const override;
  void present(Presenter& out, const Record& record) const override;

 private:
  const DsmcConfig& d_;
};

}  // namespace granboltz
