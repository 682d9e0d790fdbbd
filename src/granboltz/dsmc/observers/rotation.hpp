#pragma once
// The rotational temperature of rough particles (dsmc.roughness), T_rot = sum_j I_j |omega_j|^2
// / (n d_rot), at every row and steady; the engine measures it in its pass over the spins.
#include "granboltz/dsmc/observers/observer.hpp"
#include "granboltz/dsmc/observers/row_set.hpp"

namespace granboltz {

class RotationObserver final : public Observer {
 public:
  explicit RotationObserver(const DsmcConfig& d);

  const char* name() const override { return "rotation"; }
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

  /// The rows of T_rot, [rows], in an ensemble's rows (RatiosObserver).
  static const double* scalars(const ObserverRows& rows) { return rows.values.data(); }

 private:
  const DsmcConfig& d_;
  RowSet set_;
  std::string checkpoint_name_;  // row_set_<k>: after the species' row sets
  std::uint64_t rows_;
};

}  // namespace granboltz
