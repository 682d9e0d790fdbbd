#pragma once
// The whole gas's observables at every row (kObservables: n, V, T, the pressure tensor, the heat
// flux, ...), its central speed moments <|v - V|^{2p}> (dsmc.moments) and the Sonine coefficients
// a2, a3 from them; with steady_from their steady averages with the interval dsmc.steady_ci asks
// for. The engine measures the row in its own pass; this observer keeps, sums and presents it.
#include "granboltz/dsmc/observers/observer.hpp"
#include "granboltz/dsmc/observers/row_set.hpp"

namespace granboltz {

class MomentsObserver final : public Observer {
 public:
  explicit MomentsObserver(const DsmcConfig& d);

  const char* name() const override { return "moments"; }
  void declare(Record& record, LayoutPhase phase) const override;
  ObserverRows start(bool weighted) const override;
  void target(ObserverRows& rows, std::uint64_t m, RowTargets& out) const override;
  void observe(const ObservedRow& row, ObserverRows& rows) const override;
  void save(H5Writer& out, const std::string& group, const ObserverRows& rows,
            std::uint64_t next) const override;
  ObserverRows load(const H5Reader& in, const std::string& group, bool weighted,
                    std::uint64_t next) const override;
  void accumulate(const FinishedEnsemble& ensemble, const ObserverRows& rows,
                  Record& record) const override;
  void present(Presenter& out, const Record& record) const override;

  /// The rows of the scalars, [rows][kNumScalars], in an ensemble's rows (RatiosObserver).
  static const double* scalars(const ObserverRows& rows) { return rows.values.data(); }

 private:
  const DsmcConfig& d_;
  RowSet set_;
  std::uint64_t rows_;
};

}  // namespace granboltz
