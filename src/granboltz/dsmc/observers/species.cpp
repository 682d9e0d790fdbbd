#include "granboltz/dsmc/observers/species.hpp"

namespace granboltz {

SpeciesObserver::SpeciesObserver(const DsmcConfig& d)
    : d_(d), rows_(d.observations() + 1), P_(static_cast<std::uint64_t>(d.moments)) {
  for (const RowSet& s : extra_row_sets(d))
    if (s.width == kNumScalars) sets_.push_back(s);
}

void SpeciesObserver::declare(Record& r, LayoutPhase phase) const {
  if (phase == LayoutPhase::kGeneralGas)
    for (const RowSet& s : sets_) declare_row_set(r, d_, s);
}

ObserverRows SpeciesObserver::start(bool) const {
  ObserverRows w;
  w.values.assign(sets_.size() * stride(), 0.0);  // per species [rows][scalars], then [rows][P]
  return w;
}

void SpeciesObserver::target(ObserverRows& w, std::uint64_t m, RowTargets& out) const {
  for (std::size_t a = 0; a < sets_.size(); ++a) {
    double* base = w.values.data() + a * stride();
    out.rows.push_back(base + m * kNumScalars);
    out.row_moments.push_back(base + rows_ * kNumScalars + m * P_);
  }
}

// Checkpoints name the general gas's row sets by their place: species a is row_set_<a>.
void SpeciesObserver::save(H5Writer& out, const std::string& g, const ObserverRows& w,
                           std::uint64_t next) const {
  for (std::size_t a = 0; a < sets_.size(); ++a) {
    const double* base = w.values.data() + a * stride();
    save_row_set(out, g + "/row_set_" + std::to_string(a), sets_[a], base,
                 base + rows_ * kNumScalars, next);
  }
}

ObserverRows SpeciesObserver::load(const H5Reader& in, const std::string& g, bool weighted,
                                   std::uint64_t next) const {
  ObserverRows w = start(weighted);
  for (std::size_t a = 0; a < sets_.size(); ++a) {
    double* base = w.values.data() + a * stride();
    load_row_set(in, g + "/row_set_" + std::to_string(a), g, sets_[a], base,
                 base + rows_ * kNumScalars, next);
  }
  return w;
}

void SpeciesObserver::accumulate(const FinishedEnsemble& f, const ObserverRows& w,
                                 Record& record) const {
  for (std::size_t a = 0; a < sets_.size(); ++a) {
    const double* base = w.values.data() + a * stride();
    add_rows(d_, f.run.times, sets_[a], base, base + rows_ * kNumScalars, f.index, false, record);
  }
}

void SpeciesObserver::present(Presenter& out, const Record& record) const {
  const std::uint64_t rows = rows_, N = record.ensembles();
  for (std::size_t a = 0; a < sets_.size(); ++a) {
    const RowSet& set = sets_[a];
    write_moments(out, set.group, record.moments(set.prefix + "series"), rows, N, false);
    if (set.P)
      write_speed_moments(out, set.group, record.moments(set.prefix + "moment_series"), set.P, rows,
                          N, false);
    if (d_.steady) {
      for (const auto& o : kObservables) write_steady_observable(out, d_, record, o, 0, set);
      write_steady_speed_moments(out, d_, record, set);
    }
    write_sonine(out, d_, record, set);
    const auto& sp = d_.species[a];
    out.attr(set.group, "mass", sp.mass);
    out.attr(set.group, "diameter", sp.diameter);
    out.attr(set.group, "fraction",
             static_cast<double>(sp.count) / static_cast<double>(d_.particles));
    out.attr(set.group, "particles", sp.count);
    if (d_.roughness.on) out.attr(set.group, "inertia", sp.inertia);
  }
}

}  // namespace granboltz
