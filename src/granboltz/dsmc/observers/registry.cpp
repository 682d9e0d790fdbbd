#include "granboltz/dsmc/observers/registry.hpp"

#include "granboltz/dsmc/observers/cooling_rate.hpp"
#include "granboltz/dsmc/observers/histogram.hpp"

namespace granboltz {

std::vector<std::unique_ptr<Observer>> make_observers(const DsmcConfig& d) {
  std::vector<std::unique_ptr<Observer>> out;
  // One line per observer: whether the config asks for it, and the observer.
  if (d.histogram.shells) out.push_back(std::make_unique<HistogramObserver>(d, HistogramObserver::kRadial));
  if (d.weights.swpm && d.thermostat == Thermostat::kGaussian) out.push_back(std::make_unique<CoolingRateObserver>(d));
  if (d.histogram.shells && d.histogram.component) out.push_back(std::make_unique<HistogramObserver>(d, HistogramObserver::kComponent));
  return out;
}

}  // namespace granboltz
