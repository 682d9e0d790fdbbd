#pragma once
// The velocity histograms of dsmc.histogram: the radial one of |v - c| (GRW05 eq. 37, c the
// origin or the bulk velocity) and, with histogram.component, that of (v - V)_x. Per row the
// particles per shell (and for weighted particles the weight per shell, which is f_k itself);
// with steady_from each ensemble's time average of f_k over the steady rows.
#include "granboltz/dsmc/observers/observer.hpp"

namespace granboltz {

class HistogramObserver final : public Observer {
 public:
  enum Kind { kRadial, kComponent };
  HistogramObserver(const DsmcConfig& d, Kind kind);

  const char* name() const override { return name_.c_str(); }
  void declare(Record& record, LayoutPhase phase) const override;
  ObserverRows start(bool weighted) const override;
  void observe(const ObservedRow& row, ObserverRows& rows) const override;
  void save(H5Writer& out, const std::string& group, const ObserverRows& rows,
            std::uint64_t next) const override;
  ObserverRows load(const H5Reader& in, const std::string& group, bool weighted,
                    std::uint64_t next) const override;
  void accumulate(const FinishedEnsemble& ensemble, const ObserverRows& rows,
                  Record& record) const override;
  void present(Presenter& out, const Record& record) const override;

 private:
  const DsmcConfig& d_;
  Kind kind_;
  std::string name_;  // "histogram" or "histogram_component": accumulators and groups
  std::uint64_t rows_, K1_;
};

}  // namespace granboltz
