#pragma once
// Each species of a mixture (dsmc.species, written when there is more than one or any is named)
// as a gas of its own: its observables, speed moments and a2, a3 at every row and steady, under
// /species/<name>. The general gas's engine measures them in the same pass as the whole gas's.
#include "granboltz/dsmc/observers/observer.hpp"
#include "granboltz/dsmc/observers/row_set.hpp"

namespace granboltz {

class SpeciesObserver final : public Observer {
 public:
  explicit SpeciesObserver(const DsmcConfig& d);

  const char* name() const override { return "species"; }
  void declare(Record& record, LayoutPhase phase) const override;
  ObserverRows start(bool weighted) const override;
  void target(ObserverRows& rows, std::uint64_t m, RowTargets& out) const override;
  void save(H5Writer& out, const std::string& group, const ObserverRows& rows,
            std::uint64_t next) const override;
  ObserverRows load(const H5Reader& in, const std::string& group, bool weighted,
                    std::uint64_t next) const override;
  void accumulate(const FinishedEnsemble& ensemble, const ObserverRows& rows,
                  Record& record) const override;
  void present(Presenter& out, const Record& record) const override;

  /// Species a's rows of scalars, [rows][kNumScalars], in an ensemble's rows (RatiosObserver).
  const double* scalars(const ObserverRows& rows, std::size_t a) const {
    return rows.values.data() + a * stride();
  }

 private:
  std::uint64_t stride() const { return rows_ * (kNumScalars + P_); }  // one species' rows
  const DsmcConfig& d_;
  std::vector<RowSet> sets_;
  std::uint64_t rows_, P_;
};

}  // namespace granboltz
