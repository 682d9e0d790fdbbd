#pragma once
// Ratios x/y of two row scalars stored as observables of their own: theta = T_rot/T of rough
// particles (/theta) and T_a/T_b of the species of a mixture (/temperature_ratio/<a>_over_<b>).
// The mean is the ratio of the ensemble means; the interval the delta method with the variances
// and the covariance of (x, y) over the ensembles (docs/output.md). This observer keeps their
// cross sums, per row (prefix + "cross") and of the ensembles' steady time averages
// (prefix + "steady_cross"); the other sums they need are the row sets' own.
#include <limits>

#include "granboltz/dsmc/observers/observer.hpp"
#include "granboltz/dsmc/observers/row_set.hpp"

namespace granboltz {

/// One ratio of two scalars of the row sets.
struct RatioSet {
  std::string prefix;                  ///< of its accumulators
  std::string group;                   ///< of its datasets, and under /steady
  std::size_t x_set, y_set;            ///< row sets: 0 the whole gas, k + 1 extra_row_sets()[k]
  std::uint64_t x_k, y_k;              ///< the scalar of each row
  std::string numerator, denominator;  ///< names written as attributes (species names for T_a/T_b)
};
/// theta = T_rot/T with dsmc.roughness, then T_a/T_b for every pair a < b of dsmc.species in the
/// order the species are listed.
std::vector<RatioSet> ratio_sets(const DsmcConfig& d);

class SpeciesObserver;

class RatiosObserver final : public Observer {
 public:
  static constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();
  /// The places of the observers whose rows the ratios divide, in make_observers' order (kNone:
  /// absent); `species` must outlive this observer.
  RatiosObserver(const DsmcConfig& d, std::size_t moments, const SpeciesObserver* species,
                 std::size_t species_index, std::size_t rotation);

  const char* name() const override { return "ratios"; }
  void declare(Record& record, LayoutPhase phase) const override;
  void accumulate(const FinishedEnsemble& ensemble, const ObserverRows& rows,
                  Record& record) const override;
  void present(Presenter& out, const Record& record) const override;

 private:
  const DsmcConfig& d_;
  std::vector<RatioSet> ratios_;
  std::vector<RowSet> sets_;  // 0 the whole gas, k + 1 extra_row_sets()[k]
  std::size_t moments_, species_index_, rotation_;
  const SpeciesObserver* species_;
};

}  // namespace granboltz
