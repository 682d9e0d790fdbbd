#include "granboltz/dsmc/observers/rotation.hpp"

namespace granboltz {

namespace {
const ObservableInfo kRotational{
    "temperature_rotational", 0, 0,
    "T_rot = sum_j I_j |omega_j|^2 / (n d_rot), d_rot = 3 (d = 3) or 1 "
    "(d = 2): the rotational temperature of rough particles"};
}  // namespace

RotationObserver::RotationObserver(const DsmcConfig& d)
    : d_(d),
      set_(extra_row_sets(d).back()),
      checkpoint_name_("/row_set_" + std::to_string(extra_row_sets(d).size() - 1)),
      rows_(d.observations() + 1) {}

void RotationObserver::declare(Record& r, LayoutPhase phase) const {
  if (phase == LayoutPhase::kGeneralGas) declare_row_set(r, d_, set_);
}

ObserverRows RotationObserver::start(bool) const {
  ObserverRows w;
  w.values.assign(rows_, 0.0);
  return w;
}

void RotationObserver::target(ObserverRows& w, std::uint64_t m, RowTargets& out) const {
  out.rows.push_back(w.values.data() + m);
  out.row_moments.push_back(nullptr);  // no speed moments
}

void RotationObserver::save(H5Writer& out, const std::string& g, const ObserverRows& w,
                            std::uint64_t next) const {
  save_row_set(out, g + checkpoint_name_, set_, w.values.data(), nullptr, next);
}

ObserverRows RotationObserver::load(const H5Reader& in, const std::string& g, bool weighted,
                                    std::uint64_t next) const {
  ObserverRows w = start(weighted);
  load_row_set(in, g + checkpoint_name_, g, set_, w.values.data(), nullptr, next);
  return w;
}

void RotationObserver::accumulate(const FinishedEnsemble& f, const ObserverRows& w,
                                  Record& record) const {
  add_rows(d_, f.run.times, set_, w.values.data(), nullptr, f.index, false, record);
}

void RotationObserver::present(Presenter& out, const Record& record) const {
  write_observable(out, "", kRotational, record.moments(set_.prefix + "series"), 1, rows_,
                   record.ensembles(), false);
  if (d_.steady) write_steady_observable(out, d_, record, kRotational, 0, set_);
}

}  // namespace granboltz
