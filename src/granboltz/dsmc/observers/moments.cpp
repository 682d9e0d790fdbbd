#include "granboltz/dsmc/observers/moments.hpp"

#include <algorithm>

#include "granboltz/stats/blocking.hpp"
#include "granboltz/stats/delta_method.hpp"
#include "granboltz/stats/statistics.hpp"

namespace granboltz {

MomentsObserver::MomentsObserver(const DsmcConfig& d)
    : d_(d), set_(whole_gas_rows(d)), rows_(d.observations() + 1) {}

void MomentsObserver::declare(Record& r, LayoutPhase phase) const {
  // The one-species layout of every output since the first, around the event columns and the
  // radial histogram's sums.
  const std::uint64_t rows = rows_, P = set_.P;
  if (phase == LayoutPhase::kSeries) r.declare_moments("series", rows * kNumScalars);
  if (phase == LayoutPhase::kSteadySums) {
    if (d_.steady) {
      r.declare_moments("steady", kNumScalars);
      r.declare_total("steady_samples");
    }
    // The speed moments have sums of their own, so that the other sums keep their layout.
    if (P) r.declare_moments("moment_series", rows * P);
    if (P && d_.steady) r.declare_moments("moment_steady", P);
  }
  if (phase == LayoutPhase::kEnsembleAverages) {
    if (d_.steady) {
      // Consecutive rows of an ensemble are correlated: per ensemble its time average of every
      // scalar and speed moment, and for each blocking level the blocked variance of that
      // average. Kept with steady_ci: independent too, whose outputs show the honest interval.
      const std::uint64_t K = kNumScalars + P;
      r.declare_moments("steady_ensemble", K);
      if (const std::uint64_t L = steady_block_levels(d_))
        r.declare_moments("steady_blocks", L * K);
    }
    // a2 and a3 from M2, M4, M6: their intervals by the delta method need the ensembles' cross
    // sums (only `sum` is used). Pairs (M2, M4), then with P >= 3 (M2, M6), (M4, M6).
    if (const std::uint64_t C = cross_pairs(P)) {
      r.declare_moments("moment_cross", rows * C);
      if (d_.steady) r.declare_moments("steady_moment_cross", C);
    }
  }
}

ObserverRows MomentsObserver::start(bool) const {
  ObserverRows w;
  w.values.assign(rows_ * (set_.width + set_.P), 0.0);  // [rows][scalars], then [rows][P]
  return w;
}

void MomentsObserver::target(ObserverRows& w, std::uint64_t m, RowTargets& out) const {
  out.moments = {w.values.data() + rows_ * set_.width + m * set_.P, set_.P};
}

void MomentsObserver::observe(const ObservedRow& row, ObserverRows& w) const {
  std::copy(row.whole.begin(), row.whole.end(),
            w.values.begin() + static_cast<std::ptrdiff_t>(row.m * set_.width));
}

void MomentsObserver::save(H5Writer& out, const std::string& g, const ObserverRows& w,
                           std::uint64_t next) const {
  save_row_set(out, g, set_, w.values.data(), w.values.data() + rows_ * set_.width, next);
}

ObserverRows MomentsObserver::load(const H5Reader& in, const std::string& g, bool weighted,
                                   std::uint64_t next) const {
  ObserverRows w = start(weighted);
  load_row_set(in, g, g, set_, w.values.data(), w.values.data() + rows_ * set_.width, next);
  return w;
}

void MomentsObserver::accumulate(const FinishedEnsemble& f, const ObserverRows& w,
                                 Record& record) const {
  add_rows(d_, f.run.times, set_, w.values.data(), w.values.data() + rows_ * set_.width, f.index,
           true, record);
}

void MomentsObserver::present(Presenter& out, const Record& record) const {
  const std::uint64_t rows = rows_, N = record.ensembles(), P = set_.P;
  write_moments(out, "", record.moments("series"), rows, N, false);
  if (P) write_speed_moments(out, "", record.moments("moment_series"), P, rows, N, false);
  out.attr("/", "confidence_lambda_p", kLambdaP);
  if (d_.steady) {
    for (const auto& o : kObservables) write_steady_observable(out, d_, record, o, 0, set_);
    write_steady_speed_moments(out, d_, record, set_);
    out.attr("/steady", "estimator",
             std::string(d_.steady_ci_independent                               ? "independent"
                         : N >= kSteadyMinEnsembles || !steady_block_levels(d_) ? "ensembles"
                                                                                : "blocking"));
    out.attr("/steady", "samples", record.total("steady_samples"));
    out.attr("/steady", "from", d_.steady_from);
  }
  write_sonine(out, d_, record, set_);
}

}  // namespace granboltz
