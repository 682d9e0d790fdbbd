#include "granboltz/dsmc/observers/ratios.hpp"

#include <cmath>

#include "granboltz/dsmc/observers/moments.hpp"
#include "granboltz/dsmc/observers/rotation.hpp"
#include "granboltz/dsmc/observers/species.hpp"
#include "granboltz/stats/delta_method.hpp"
#include "granboltz/stats/statistics.hpp"

namespace granboltz {

namespace {
/// The offset of T in an Observation (kObservables).
constexpr std::uint64_t kTemperature = 4;
}  // namespace

std::vector<RatioSet> ratio_sets(const DsmcConfig& d) {
  std::vector<RatioSet> out;
  const std::size_t extra = extra_row_sets(d).size();
  // T_rot is the last extra row set, its only scalar; T the whole gas's (translational).
  if (d.roughness.on)
    out.push_back(
        {"theta_", "/theta", extra, 0, 0, kTemperature, "temperature_rotational", "temperature"});
  if (d.species_written)
    for (std::size_t a = 0; a < d.species.size(); ++a)
      for (std::size_t b = a + 1; b < d.species.size(); ++b) {
        const std::string& x = d.species[a].name;
        const std::string& y = d.species[b].name;
        out.push_back({"ratio_" + std::to_string(a) + "_" + std::to_string(b) + "_",
                       "/temperature_ratio/" + x + "_over_" + y, a + 1, b + 1, kTemperature,
                       kTemperature, x, y});
      }
  return out;
}

RatiosObserver::RatiosObserver(const DsmcConfig& d, std::size_t moments,
                               const SpeciesObserver* species, std::size_t species_index,
                               std::size_t rotation)
    : d_(d),
      ratios_(ratio_sets(d)),
      moments_(moments),
      species_index_(species_index),
      rotation_(rotation),
      species_(species) {
  sets_.push_back(whole_gas_rows(d));
  for (const RowSet& s : extra_row_sets(d)) sets_.push_back(s);
}

void RatiosObserver::declare(Record& r, LayoutPhase phase) const {
  if (phase != LayoutPhase::kRatios) return;
  const std::uint64_t rows = d_.observations() + 1;
  for (const RatioSet& x : ratios_) {
    r.declare_moments(x.prefix + "cross", rows);
    if (d_.steady) r.declare_moments(x.prefix + "steady_cross", 1);
  }
}

// One ensemble's cross sums: x y per row and, with steady_from, the product of its time averages
// of x and y over the steady rows, each summed as add_rows sums them (in row order, then divided
// by R), so that they are the averages in steady_ensemble.
void RatiosObserver::accumulate(const FinishedEnsemble& f, const ObserverRows&,
                                Record& record) const {
  // The rows of each row set, as sets_ orders them.
  std::vector<const double*> obs{MomentsObserver::scalars(f.rows[moments_])};
  if (species_)
    for (std::size_t a = 0; a + 1 < sets_.size() && sets_[a + 1].width == kNumScalars; ++a)
      obs.push_back(species_->scalars(f.rows[species_index_], a));
  if (rotation_ != kNone) obs.push_back(RotationObserver::scalars(f.rows[rotation_]));

  const std::vector<double>& times = f.run.times;
  const double after = steady_after(d_);
  const std::uint64_t rows = times.size();
  std::uint64_t first = 0;
  while (first < rows && !(times[first] > after)) ++first;
  auto average = [&](const double* o, std::uint64_t W) {
    double sum = 0.0;
    for (std::uint64_t m = first; m < rows; ++m) sum += o[m * W];
    return sum / static_cast<double>(rows - first);
  };
  for (const RatioSet& r : ratios_) {
    const double* x = obs[r.x_set] + r.x_k;
    const double* y = obs[r.y_set] + r.y_k;
    const std::uint64_t wx = sets_[r.x_set].width, wy = sets_[r.y_set].width;
    auto& cross = record.moments(r.prefix + "cross");
    for (std::uint64_t m = 0; m < rows; ++m) cross[m].sum.add(x[m * wx] * y[m * wy]);
    if (d_.steady && first < rows)
      record.moments(r.prefix + "steady_cross")[0].sum.add(average(x, wx) * average(y, wy));
  }
}

namespace {
/// The datasets of one ratio (ratio_sets): <group>/{mean,ci,bias} [M+1] and with steady_from
/// /steady<group>/{mean,sigma,ci,bias}, as a2's.
void write_ratio(Presenter& out, const DsmcConfig& d, const Record& record,
                 const std::vector<RowSet>& sets, const RatioSet& r) {
  const std::uint64_t rows = d.observations() + 1, N = record.ensembles();
  if (N == 0) return;
  const RowSet &X = sets[r.x_set], &Y = sets[r.y_set];
  const std::string what = r.group == "/theta" ? "theta = T_rot/T (T translational)"
                                               : "T_" + r.numerator + "/T_" + r.denominator +
                                                     ", the species' temperatures";
  const std::string bias_text =
      "; bias: the ratio estimator's leading 1/N bias (second-order delta method), not "
      "subtracted from mean";
  const std::string how =
      ": the ratio of the ensemble means; ci by the delta method with the "
      "variances and the covariance of the two over the ensembles" +
      bias_text;
  const std::string steady_how =
      ": the ratio of the steady averages; ci by the delta method with the variances and the "
      "covariance of the ensembles' time averages over t_m > steady_from" +
      bias_text;
  const auto& sx = record.moments(X.prefix + "series");
  const auto& sy = record.moments(Y.prefix + "series");
  const auto& cross = record.moments(r.prefix + "cross");
  std::vector<double> mean(rows), ci(rows), bias(rows);
  for (std::uint64_t m = 0; m < rows; ++m) {
    const Moments2 &x = sx[m * X.width + r.x_k], &y = sy[m * Y.width + r.y_k];
    const RatioStats s =
        ratio_of_means(x.sum.value() / static_cast<double>(N),
                       y.sum.value() / static_cast<double>(N), x, y, cross[m], N, false);
    mean[m] = s.mean;
    ci[m] = kLambdaP * std::sqrt(s.variance);
    bias[m] = s.bias;
  }
  auto attrs = [&](const std::string& g, const std::string& text) {
    out.attr(g, "description", what + text);
    out.attr(g, "numerator", r.numerator);
    out.attr(g, "denominator", r.denominator);
  };
  out.write(r.group + "/mean", mean, {rows}, what + "; per row t_m: the ratio of the means");
  out.write(r.group + "/ci", ci, {rows}, "confidence half-width of " + r.group + "/mean");
  out.write(r.group + "/bias", bias, {rows}, "the leading 1/N bias of " + r.group + "/mean");
  attrs(r.group, how);
  if (!d.steady) return;
  // Each ensemble's time averages over the steady rows are one independent sample (as /steady/a2,
  // whatever steady_ci says); the mean is the ratio of the steady means, as a user divides them.
  const std::uint64_t S = record.total("steady_samples");
  const Moments2& x = record.moments(X.prefix + "steady_ensemble")[r.x_k];
  const Moments2& y = record.moments(Y.prefix + "steady_ensemble")[r.y_k];
  const RatioStats s = ratio_of_means(record.moments(X.prefix + "steady")[r.x_k].stats(S).mean,
                                      record.moments(Y.prefix + "steady")[r.y_k].stats(S).mean, x,
                                      y, record.moments(r.prefix + "steady_cross")[0], N, true);
  const double sigma = N >= 2 ? std::sqrt(s.variance) : NAN;
  const std::string g = "/steady" + r.group;
  out.write(g + "/mean", std::vector<double>{s.mean}, {},
            what + "; steady: the ratio of the steady means");
  out.write(g + "/sigma", std::vector<double>{sigma}, {}, "the standard error of " + g + "/mean");
  const double factor = confidence_factor(static_cast<double>(N) - 1);
  out.write(g + "/ci", std::vector<double>{factor * sigma}, {},
            "confidence half-width of " + g + "/mean");
  out.write(g + "/bias", std::vector<double>{N >= 2 ? s.bias : NAN}, {},
            "the leading 1/N bias of " + g + "/mean");
  attrs(g, steady_how);
  out.attr(g, "estimator", std::string("ensembles"));
  out.attr(g, "samples", S);
  out.attr(g, "from", d.steady_from);
}
}  // namespace

void RatiosObserver::present(Presenter& out, const Record& record) const {
  for (const RatioSet& r : ratios_) write_ratio(out, d_, record, sets_, r);
}

}  // namespace granboltz
