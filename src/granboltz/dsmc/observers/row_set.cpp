#include "granboltz/dsmc/observers/row_set.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "granboltz/config/reader.hpp"
#include "granboltz/stats/blocking.hpp"
#include "granboltz/stats/delta_method.hpp"
#include "granboltz/stats/statistics.hpp"

namespace granboltz {

std::vector<double> dsmc_times(const DsmcConfig& d) {
  if (!d.observe_times.empty()) {  // dsmc.observe: the times as read
    std::vector<double> t{0.0};
    t.insert(t.end(), d.observe_times.begin(), d.observe_times.end());
    return t;
  }
  const std::uint64_t M = d.observations();
  std::vector<double> t(M + 1);
  for (std::uint64_t m = 0; m <= M; ++m)
    t[m] = m == M ? d.t_end : static_cast<double>(m) * d.observe_every;
  return t;
}

RowSet whole_gas_rows(const DsmcConfig& d) {
  return {"", "", kNumScalars, static_cast<std::uint64_t>(d.moments)};
}

std::uint64_t steady_rows(const DsmcConfig& d) {
  if (!d.steady) return 0;
  std::uint64_t rows = 0;
  for (double t : dsmc_times(d)) rows += t > d.steady_from + 1e-9 * d.observe_every;
  return rows;
}

std::uint64_t steady_block_levels(const DsmcConfig& d) { return block_levels(steady_rows(d)); }

std::vector<RowSet> extra_row_sets(const DsmcConfig& d) {
  std::vector<RowSet> out;
  if (d.species_written)
    for (std::size_t a = 0; a < d.species.size(); ++a)
      out.push_back({"species_" + std::to_string(a) + "_", "/species/" + d.species[a].name,
                     static_cast<std::uint64_t>(kNumScalars),
                     static_cast<std::uint64_t>(d.moments)});
  if (d.roughness.on) out.push_back({"rotation_", "", 1, 0});
  return out;
}

double steady_after(const DsmcConfig& d) { return d.steady_from + 1e-9 * d.observe_every; }

void declare_row_set(Record& r, const DsmcConfig& d, const RowSet& s) {
  const std::uint64_t rows = d.observations() + 1, W = s.width, P = s.P;
  r.declare_moments(s.prefix + "series", rows * W);
  if (d.steady) r.declare_moments(s.prefix + "steady", W);
  if (P) r.declare_moments(s.prefix + "moment_series", rows * P);
  if (P && d.steady) r.declare_moments(s.prefix + "moment_steady", P);
  if (d.steady) {
    r.declare_moments(s.prefix + "steady_ensemble", W + P);
    if (const std::uint64_t L = steady_block_levels(d))
      r.declare_moments(s.prefix + "steady_blocks", L * (W + P));
  }
  if (const std::uint64_t C = cross_pairs(P)) {
    r.declare_moments(s.prefix + "moment_cross", rows * C);
    if (d.steady) r.declare_moments(s.prefix + "steady_moment_cross", C);
  }
}

void save_row_set(H5Writer& out, const std::string& g, const RowSet& s, const double* obs,
                  const double* moments, std::uint64_t next) {
  out.write(g + "/observations", std::vector<double>(obs, obs + next * s.width), {next, s.width});
  if (s.P)
    out.write(g + "/moment_observations", std::vector<double>(moments, moments + next * s.P),
              {next, s.P});
}

void load_row_set(const H5Reader& in, const std::string& g, const std::string& ensemble_group,
                  const RowSet& s, double* obs, double* moments, std::uint64_t next) {
  auto fits = [&](const std::string& path, std::uint64_t width) {
    return in.exists(path) && in.dims(path) == Dims{next, width};
  };
  if (!fits(g + "/observations", s.width) || (s.P && !fits(g + "/moment_observations", s.P)))
    throw std::runtime_error(in.path() + ": malformed ensemble state " + ensemble_group);
  const auto o = in.read_double(g + "/observations");
  std::copy(o.begin(), o.end(), obs);
  if (s.P) {
    const auto mm = in.read_double(g + "/moment_observations");
    std::copy(mm.begin(), mm.end(), moments);
  }
}

namespace {
// An observable that overflowed: named with the values that make a run overflow, instead of
// the exact sums' bare refusal of a non-finite number.
[[noreturn]] void throw_not_finite(int k, double value, double t, std::uint64_t e) {
  const char* name = "an observable";
  for (const auto& o : kObservables) {
    if (k < 0) break;
    const int width = o.rank == 0 ? 1 : o.rank == 1 ? 3 : 9;
    if (k >= o.offset && k < o.offset + width) name = o.name;
  }
  throw std::runtime_error(std::string("dsmc: ") + name + " = " + format_real(value) +
                           " at t = " + format_real(t) + " in ensemble " + std::to_string(e) +
                           ": the simulation overflowed; are dsmc.beta, dsmc.initial.temperature "
                           "or dsmc.kernel.C far too large?");
}

/// One ensemble's contribution to steady_ensemble and steady_blocks. Computed from its rows alone
/// in a fixed order, so the same ensemble always adds the same doubles to the exact sums.
void add_steady_blocks(const DsmcConfig& d, const std::vector<double>& times, const RowSet& set,
                       const double* obs, const double* moments, Record& record) {
  const double after = steady_after(d);
  const std::uint64_t P = set.P, W = set.width;
  const std::uint64_t K = W + P, L = steady_block_levels(d);
  std::uint64_t first = 0;
  while (first < times.size() && !(times[first] > after)) ++first;
  const std::uint64_t R = times.size() - first;
  auto& ens = record.moments(set.prefix + "steady_ensemble");
  auto* blocks = L ? &record.moments(set.prefix + "steady_blocks") : nullptr;
  std::vector<double> x(R), avg(K);
  for (std::uint64_t k = 0; k < K; ++k) {
    for (std::uint64_t i = 0; i < R; ++i)
      x[i] = k < W ? obs[(first + i) * W + k] : moments[(first + i) * P + (k - W)];
    avg[k] = row_average(x.data(), R);
    ens[k].add(avg[k]);
    for (std::uint64_t l = 0; l < L; ++l)
      (*blocks)[l * K + k].add(blocked_variance(x.data(), R, std::uint64_t{1} << l));
  }
  if (cross_pairs(P))
    add_cross(record.moments(set.prefix + "steady_moment_cross").data(), &avg[W], P);
}
}  // namespace

/// Adds one ensemble's rows of a row set to its accumulators: the series, the speed moments and
/// their cross products, and with steady_from the steady sums and the per-ensemble averages and
/// blocks. `count_samples`: the first set counts the steady samples for all.
void add_rows(const DsmcConfig& d, const std::vector<double>& times, const RowSet& set,
              const double* obs, const double* moments, std::uint64_t e, bool count_samples,
              Record& record) {
  const double after = steady_after(d);
  const std::uint64_t rows = times.size(), W = set.width, P = set.P;
  auto& series = record.moments(set.prefix + "series");
  for (std::uint64_t m = 0; m < rows; ++m) {
    const double* o = obs + m * W;
    for (std::uint64_t k = 0; k < W; ++k)
      if (!std::isfinite(o[k]))
        throw_not_finite(set.group.empty() && W == kNumScalars ? static_cast<int>(k) : -1, o[k],
                         times[m], e);
    for (std::uint64_t k = 0; k < W; ++k) series[m * W + k].add(o[k]);
    const double* mm = moments + m * P;
    if (P) {
      // After the other observables, so that a run overflowing anyway fails as before.
      for (std::uint64_t k = 0; k < P; ++k)
        if (!(std::fabs(mm[k]) <= kMomentLimit))
          throw std::runtime_error(
              "dsmc.moments = " + std::to_string(P) + ": " + moment_name(static_cast<int>(k) + 1) +
              " = " + format_real(mm[k]) + " at t = " + format_real(times[m]) + " in ensemble " +
              std::to_string(e) +
              " exceeds 1e150 (its square would overflow); ask for fewer moments");
      auto& mseries = record.moments(set.prefix + "moment_series");
      for (std::uint64_t k = 0; k < P; ++k) mseries[m * P + k].add(mm[k]);
      if (const std::uint64_t C = cross_pairs(P))
        add_cross(record.moments(set.prefix + "moment_cross").data() + m * C, mm, P);
    }
    if (d.steady && times[m] > after) {
      auto& steady = record.moments(set.prefix + "steady");
      for (std::uint64_t k = 0; k < W; ++k) steady[k].add(o[k]);
      if (P) {
        auto& msteady = record.moments(set.prefix + "moment_steady");
        for (std::uint64_t k = 0; k < P; ++k) msteady[k].add(mm[k]);
      }
      if (count_samples) ++record.total("steady_samples");
    }
  }
  if (d.steady) add_steady_blocks(d, times, set, obs, moments, record);
}

SteadyStats row_set_steady_stats(const DsmcConfig& d, const Record& record, const RowSet& set,
                                 std::uint64_t k, bool batch) {
  const std::uint64_t P = set.P, W = set.width;
  const std::string& x = set.prefix;
  const std::uint64_t S = record.total("steady_samples"), N = record.ensembles();
  const MeanCi all = k < W ? record.moments(x + "steady")[k].stats(S)
                           : record.moments(x + "moment_steady")[k - W].stats(S);
  const std::uint64_t K = W + P, L = steady_block_levels(d);
  // Blocking within the ensembles (Flyvbjerg & Petersen 1989) only where too few ensembles give
  // a spread of their own.
  const SteadyEstimator how = d.steady_ci_independent && !batch    ? SteadyEstimator::kIndependent
                              : N >= kSteadyMinEnsembles || L == 0 ? SteadyEstimator::kEnsembles
                                                                   : SteadyEstimator::kBlocking;
  std::vector<double> blocked;
  if (how == SteadyEstimator::kBlocking)
    for (std::uint64_t l = 0; l < L; ++l)
      blocked.push_back(record.moments(x + "steady_blocks")[l * K + k].sum.value());
  return steady_interval(how, all, S, N, steady_rows(d), record.moments(x + "steady_ensemble")[k],
                         blocked);
}

namespace {
Dims shape_of(const ObservableInfo& o, std::uint64_t rows) {
  if (o.rank == 0) return {rows};
  if (o.rank == 1) return {rows, 3};
  return {rows, 3, 3};
}
}  // namespace

/// Writes mean, ci and variance of observable `o` from sums laid out as [rows][stride].
void write_observable(Presenter& out, const std::string& prefix, const ObservableInfo& o,
                      const std::vector<Moments2>& sums, std::uint64_t stride, std::uint64_t rows,
                      std::uint64_t samples, bool scalar_rows) {
  const int size = observable_size(o);
  std::vector<double> mean, ci, var;
  for (std::uint64_t m = 0; m < rows; ++m)
    for (int k = 0; k < size; ++k) {
      const MeanCi s = sums[m * stride + o.offset + k].stats(samples);
      mean.push_back(s.mean);
      ci.push_back(s.ci);
      var.push_back(s.variance);
    }
  Dims dims = shape_of(o, rows);
  if (scalar_rows) dims.erase(dims.begin());
  const std::string g = prefix + "/" + o.name;
  const std::string what = std::string(o.description) + (scalar_rows ? "" : "; per row t_m");
  out.write(g + "/mean", mean, dims, what + ": mean over the ensembles");
  out.write(g + "/ci", ci, dims,
            what + ": confidence half-width (lambda_p: root attribute confidence_lambda_p)");
  out.write(g + "/variance", var, dims, what + ": variance over the ensembles");
  out.attr(g, "description", std::string(o.description));
}

/// The /steady group of one observable: mean, ci, variance as write_observable, plus sigma and
/// the estimator's attributes (the largest tau_int over the components, the smallest N_eff).
/// With steady_ci: independent the batch estimator's sigma and ci follow in a `batch` subgroup.
void write_steady_observable(Presenter& out, const DsmcConfig& d, const Record& record,
                             const ObservableInfo& o, std::uint64_t base, const RowSet& set) {
  const int size = observable_size(o);
  const std::string g = "/steady" + set.group + "/" + std::string(o.name);
  Dims dims = shape_of(o, 1);
  dims.erase(dims.begin());
  auto write = [&](const std::string& group, bool batch) {
    std::vector<double> mean, ci, var, sigma;
    double tau = 0.0, neff = 0.0;
    std::uint64_t block_rows = 0;
    const char* estimator = "independent";
    for (int k = 0; k < size; ++k) {
      const SteadyStats s = row_set_steady_stats(
          d, record, set, base + static_cast<std::uint64_t>(o.offset + k), batch);
      mean.push_back(s.mean);
      ci.push_back(s.ci);
      var.push_back(s.variance);
      sigma.push_back(s.sigma);
      if (k == 0 || s.tau_int > tau || std::isnan(s.tau_int)) tau = s.tau_int;
      if (k == 0 || s.effective_samples < neff || std::isnan(s.effective_samples))
        neff = s.effective_samples;
      block_rows = std::max(block_rows, s.block_rows);
      estimator = s.estimator;
    }
    if (group == g) {
      const std::string what =
          std::string(o.description) + "; steady average over t_m > steady_from";
      out.write(g + "/mean", mean, dims, what + ": mean");
      out.write(g + "/ci", ci, dims, what + ": confidence half-width");
      out.write(g + "/variance", var, dims, what + ": variance");
      out.attr(g, "description", std::string(o.description));
    } else {
      out.write(group + "/ci", ci, dims,
                "the batch estimator's confidence half-width of " + g + "/mean");
      out.attr(group, "description",
               std::string("the batch estimator's interval (dsmc.steady_ci: batch), which "
                           "accounts for the correlation of consecutive rows"));
    }
    out.write(group + "/sigma", sigma, dims,
              "the standard error of " + g + "/mean (" + estimator + ")");
    out.attr(group, "estimator", std::string(estimator));
    out.attr(group, "tau_int", tau);
    out.attr(group, "effective_samples", neff);
    out.attr(group, "samples", record.total("steady_samples"));
    out.attr(group, "from", d.steady_from);
    if (std::string(estimator) == "blocking") out.attr(group, "block_rows", block_rows);
  };
  write(g, false);
  if (d.steady_ci_independent) write(g + "/batch", true);
}

void write_moments(Presenter& out, const std::string& prefix, const std::vector<Moments2>& sums,
                   std::uint64_t rows, std::uint64_t samples, bool scalar_rows) {
  for (const auto& o : kObservables)
    write_observable(out, prefix, o, sums, kNumScalars, rows, samples, scalar_rows);
}

namespace {
/// The speed moment <|v - V|^{2(k+1)}> as an observable: its name and description are held
/// here, since ObservableInfo only points at them.
struct SpeedMoment {
  std::string name, description;
  int k;
  explicit SpeedMoment(std::uint64_t index)
      : name(moment_name(static_cast<int>(index) + 1)),
        description("<|v - V|^" + std::to_string(2 * (index + 1)) +
                    ">: the central speed moment of order " + std::to_string(2 * (index + 1)) +
                    " (dsmc.moments)"),
        k(static_cast<int>(index)) {}
  ObservableInfo info() const { return {name.c_str(), k, 0, description.c_str()}; }
};
}  // namespace

/// The speed moments moment_2 ... moment_2P, from sums laid out as [rows][P].
void write_speed_moments(Presenter& out, const std::string& prefix,
                         const std::vector<Moments2>& sums, std::uint64_t P, std::uint64_t rows,
                         std::uint64_t samples, bool scalar_rows) {
  for (std::uint64_t k = 0; k < P; ++k)
    write_observable(out, prefix, SpeedMoment(k).info(), sums, P, rows, samples, scalar_rows);
}

void write_steady_speed_moments(Presenter& out, const DsmcConfig& d, const Record& record,
                                const RowSet& set) {
  for (std::uint64_t k = 0; k < set.P; ++k)
    write_steady_observable(out, d, record, SpeedMoment(k).info(), set.width, set);
}

namespace {

const char* const kA2Description =
    "a2 = 3/5 M4/M2^2 - 1, the second Sonine coefficient from the ensemble means of the speed "
    "moments (d = 3); ci by the delta method over the ensembles; bias: the ratio estimator's "
    "leading 1/N bias (second-order delta method), not subtracted from mean";
const char* const kA3Description =
    "a3 = 1 + 3 a2 - 9/35 M6/M2^3, the third Sonine coefficient from the ensemble means of the "
    "speed moments (d = 3); ci by the delta method over the ensembles; bias: the ratio "
    "estimator's leading 1/N bias (second-order delta method), not subtracted from mean";
const char* const kA2Description2 =
    "a2 = 1/2 M4/M2^2 - 1, the second Sonine coefficient from the ensemble means of the speed "
    "moments (d = 2); ci by the delta method over the ensembles; bias: the ratio estimator's "
    "leading 1/N bias (second-order delta method), not subtracted from mean";
const char* const kA3Description2 =
    "a3 = 1 + 3 a2 - 1/6 M6/M2^3, the third Sonine coefficient from the ensemble means of the "
    "speed moments (d = 2); ci by the delta method over the ensembles; bias: the ratio "
    "estimator's leading 1/N bias (second-order delta method), not subtracted from mean";

}  // namespace

void write_sonine(Presenter& out, const DsmcConfig& d, const Record& record, const RowSet& set) {
  const std::uint64_t P = set.P;
  const std::string& x = set.prefix;
  const std::uint64_t C = cross_pairs(P), N = record.ensembles();
  if (!C || N == 0) return;
  const std::string a2_text = d.dimension == 2 ? kA2Description2 : kA2Description;
  const std::string a3_text = d.dimension == 2 ? kA3Description2 : kA3Description;
  const std::uint64_t rows = d.observations() + 1;
  const auto& series = record.moments(x + "moment_series");
  const auto& cross = record.moments(x + "moment_cross");
  std::vector<double> a2(rows), a2ci(rows), a2bias(rows), a3(rows), a3ci(rows), a3bias(rows);
  for (std::uint64_t m = 0; m < rows; ++m) {
    const Sonine s = sonine(&series[m * P], &cross[m * C], P, N, false, d.dimension);
    a2[m] = s.a2;
    a2ci[m] = kLambdaP * std::sqrt(s.var_a2);
    a2bias[m] = s.bias_a2;
    a3[m] = s.a3;
    a3ci[m] = kLambdaP * std::sqrt(s.var_a3);
    a3bias[m] = s.bias_a3;
  }
  const std::string a2g = set.group + "/a2", a3g = set.group + "/a3";
  out.write(a2g + "/mean", a2, {rows}, a2_text + "; per row t_m: mean");
  out.write(a2g + "/ci", a2ci, {rows}, "confidence half-width of " + a2g + "/mean");
  out.write(a2g + "/bias", a2bias, {rows}, "the leading 1/N bias of " + a2g + "/mean");
  out.attr(a2g, "description", a2_text);
  if (P >= 3) {
    out.write(a3g + "/mean", a3, {rows}, a3_text + "; per row t_m: mean");
    out.write(a3g + "/ci", a3ci, {rows}, "confidence half-width of " + a3g + "/mean");
    out.write(a3g + "/bias", a3bias, {rows}, "the leading 1/N bias of " + a3g + "/mean");
    out.attr(a3g, "description", a3_text);
  }
  if (!d.steady) return;
  // Steady: each ensemble's time averages of M2, M4, M6 are one independent sample.
  const Sonine s =
      sonine(&record.moments(x + "steady_ensemble")[set.width],
             record.moments(x + "steady_moment_cross").data(), P, N, true, d.dimension);
  const double factor = confidence_factor(static_cast<double>(N) - 1);
  for (int which = 2; which <= (P >= 3 ? 3 : 2); ++which) {
    const std::string g = "/steady" + set.group + "/a" + std::to_string(which);
    const double sigma = N >= 2 ? std::sqrt(which == 2 ? s.var_a2 : s.var_a3) : NAN;
    const std::string what =
        (which == 2 ? a2_text : a3_text) + "; steady, from the ensembles' time averages";
    out.write(g + "/mean", std::vector<double>{which == 2 ? s.a2 : s.a3}, {}, what + ": mean");
    out.write(g + "/sigma", std::vector<double>{sigma}, {}, "the standard error of " + g + "/mean");
    out.write(g + "/ci", std::vector<double>{factor * sigma}, {},
              "confidence half-width of " + g + "/mean");
    out.write(g + "/bias", std::vector<double>{which == 2 ? s.bias_a2 : s.bias_a3}, {},
              "the leading 1/N bias of " + g + "/mean");
    out.attr(g, "description", which == 2 ? a2_text : a3_text);
    out.attr(g, "estimator", std::string("ensembles"));
    out.attr(g, "samples", record.total("steady_samples"));
    out.attr(g, "from", d.steady_from);
  }
}

}  // namespace granboltz
