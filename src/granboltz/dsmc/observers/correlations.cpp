#include "granboltz/dsmc/observers/correlations.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "granboltz/stats/statistics.hpp"

namespace granboltz {

namespace {
double component(const Vec3& v, int a) { return a == 0 ? v.x : a == 1 ? v.y : v.z; }
}  // namespace

CorrelationsObserver::CorrelationsObserver(const DsmcConfig& d) : d_(d) {
  const auto dim = static_cast<std::uint64_t>(d.dimension);
  const std::uint64_t pairs = d.dimension == 2 ? 1 : 3;
  if (d.correlations.velocity.on) {
    if (d.species_written) {
      for (std::size_t a = 0; a < d.species.size(); ++a)
        channels_.push_back({kVelocity, 0, a, d.correlations.velocity.particles * dim,
                             "/correlations/velocity/" + d.species[a].name,
                             "correlation_velocity_" + d.species[a].name});
    } else {
      channels_.push_back({kVelocity, 0, 0, d.correlations.velocity.particles * dim,
                           "/correlations/velocity", "correlation_velocity"});
    }
  }
  if (d.correlations.stress.on) {
    channels_.push_back({kStress, 1, 0, pairs, "/correlations/stress", "correlation_stress"});
    channels_.push_back(
        {kNormalStress, 1, 0, pairs, "/correlations/normal_stress", "correlation_normal_stress"});
  }
  if (d.correlations.heat_flux.on)
    channels_.push_back({kHeatFlux, 2, 0, dim, "/correlations/heat_flux", "correlation_heat_flux"});
}

const CorrelationSpec& CorrelationsObserver::spec(int k) const {
  const CorrelationsSpec& c = d_.correlations;
  return k == 0 ? c.velocity : k == 1 ? c.stress : c.heat_flux;
}

MultipleTauCorrelator::Resolution CorrelationsObserver::resolution(int k) const {
  const CorrelationSpec& x = spec(k);
  return {x.points, x.averaging, x.levels};
}

double CorrelationsObserver::sample_time(int k, std::uint64_t index) const {
  return spec(k).time(index, d_.t_end);
}

void CorrelationsObserver::declare(Record& record, LayoutPhase phase) const {
  if (phase != LayoutPhase::kAppended) return;
  for (const Channel& c : channels_) {
    const std::uint64_t L = MultipleTauCorrelator::lag_count(resolution(c.spec));
    record.declare_moments(c.key, L);
    record.declare_moments(c.key + "_cross", L * (L + 1) / 2);
    record.declare_moments(c.key + "_lag0", 1);
  }
}

ObserverRows CorrelationsObserver::start(bool) const {
  ObserverRows w;
  w.counts.assign(3, 0);  // the next sample of velocity, stress, heat flux
  for (const Channel& c : channels_) w.correlators.emplace_back(c.width, resolution(c.spec));
  return w;
}

double CorrelationsObserver::next_sample(const ObserverRows& w) const {
  double t = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k)
    if (spec(k).on && w.counts[k] < spec(k).samples) t = std::min(t, sample_time(k, w.counts[k]));
  return t;
}

void CorrelationsObserver::sample(const ParticleView& view, double t, ObserverRows& w) const {
  bool due[3] = {false, false, false};
  for (int k = 0; k < 3; ++k)
    due[k] = spec(k).on && w.counts[k] < spec(k).samples && sample_time(k, w.counts[k]) == t;
  const int d = d_.dimension;
  auto mass = [&](std::size_t a) { return d_.general() ? d_.species[a].mass : 1.0; };

  // The bulk velocity: a lazy view knows it (conserved); otherwise summed in particle order.
  // A lazy view's true velocities are V + f (w - V): the sums below run over w - V and are scaled
  // by the powers of f, and the tagged particles are all the velocity correlation reads.
  const double f = view.bulk ? view.scale : 1.0;
  double V[3] = {0, 0, 0};
  if (view.bulk) {
    for (int x = 0; x < d; ++x) V[x] = component(*view.bulk, x);
  } else {
    double M = 0.0, P[3] = {0, 0, 0};
    for (std::size_t a = 0; a < view.species.size(); ++a) {
      const SpeciesBlock& b = view.species[a];
      const double m = mass(a);
      for (std::size_t i = b.offset; i < b.offset + b.count; ++i) {
        M += m;
        for (int x = 0; x < d; ++x) P[x] += m * component(view.particles[i].v, x);
      }
    }
    for (int x = 0; x < d; ++x) V[x] = P[x] / M;
  }
  const double n = static_cast<double>(view.particles.size());

  if (due[1] || due[2]) {
    // One pass: the kinetic energy, the stress sums and the energy flux; or none, when the engine
    // keeps these sums itself (about the conserved mean, so that sum c vanishes: the drift term
    // is round-off there and left out).
    double energy = 0.0, shear[3] = {0, 0, 0}, normal[3] = {0, 0, 0}, flux[3] = {0, 0, 0},
           drift[3] = {0, 0, 0};
    if (const double* q = view.sums) {
      energy = q[0] + q[1] + q[2];
      shear[0] = q[3];
      normal[0] = q[0] - q[1];
      if (d == 3) {
        shear[1] = q[4];
        shear[2] = q[5];
        normal[1] = q[1] - q[2];
        normal[2] = q[2] - q[0];
      }
      for (int x = 0; x < d; ++x) flux[x] = 0.5 * q[6 + x];
    }
    for (std::size_t a = 0; !view.sums && a < view.species.size(); ++a) {
      const SpeciesBlock& b = view.species[a];
      const double m = mass(a);
      for (std::size_t i = b.offset; i < b.offset + b.count; ++i) {
        double c[3] = {0, 0, 0};
        for (int x = 0; x < d; ++x) c[x] = component(view.particles[i].v, x) - V[x];
        const double c2 = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
        energy += m * c2;
        shear[0] += m * c[0] * c[1];
        normal[0] += m * (c[0] * c[0] - c[1] * c[1]);
        if (d == 3) {
          shear[1] += m * c[0] * c[2];
          shear[2] += m * c[1] * c[2];
          normal[1] += m * (c[1] * c[1] - c[2] * c[2]);
          normal[2] += m * (c[2] * c[2] - c[0] * c[0]);
        }
        for (int x = 0; x < d; ++x) {
          flux[x] += c[x] * (0.5 * m * c2);
          drift[x] += c[x];
        }
      }
    }
    if (view.bulk) {
      const double f2 = f * f, f3 = f2 * f;
      energy *= f2;
      for (int x = 0; x < 3; ++x) {
        shear[x] *= f2;
        normal[x] *= f2;
        flux[x] *= f3;
        drift[x] *= f;
      }
    }
    const double T = energy / (n * d), root = std::sqrt(n);
    for (std::size_t j = 0; j < channels_.size(); ++j) {
      const Channel& ch = channels_[j];
      double s[3];
      if (ch.signal == kStress && due[1]) {
        for (std::uint64_t x = 0; x < ch.width; ++x) s[x] = shear[x] / root;
      } else if (ch.signal == kNormalStress && due[1]) {
        for (std::uint64_t x = 0; x < ch.width; ++x) s[x] = 0.5 * normal[x] / root;
      } else if (ch.signal == kHeatFlux && due[2]) {
        for (int x = 0; x < d; ++x) s[x] = (flux[x] - 0.5 * (d + 2) * T * drift[x]) / root;
      } else {
        continue;
      }
      w.correlators[j].add({s, ch.width});
    }
  }
  if (due[0]) {
    std::vector<double> c;
    for (std::size_t j = 0; j < channels_.size(); ++j) {
      const Channel& ch = channels_[j];
      if (ch.signal != kVelocity) continue;
      const SpeciesBlock& b = view.species[ch.species];
      c.assign(ch.width, 0.0);
      const std::uint64_t tagged = d_.correlations.velocity.particles;
      for (std::uint64_t i = 0; i < tagged; ++i)
        for (int x = 0; x < d; ++x)
          c[i * d + x] = view.bulk ? f * (component(view.particles[b.offset + i].v, x) - V[x])
                                   : component(view.particles[b.offset + i].v, x) - V[x];
      w.correlators[j].add(c);
    }
  }
  for (int k = 0; k < 3; ++k)
    if (due[k]) ++w.counts[k];
}

void CorrelationsObserver::save(H5Writer& out, const std::string& g, const ObserverRows& w,
                                std::uint64_t) const {
  const std::string base = g + "/correlations";
  out.write(base + "/next_sample", w.counts, {w.counts.size()});
  for (std::size_t j = 0; j < channels_.size(); ++j) {
    const auto& s = w.correlators[j].state();
    const std::string x = base + "/" + std::to_string(j);
    out.write(x + "/shift", s.shift, {s.shift.size()});
    out.write(x + "/block", s.block, {s.block.size()});
    out.write(x + "/fill", s.fill, {s.fill.size()});
    out.write(x + "/in_block", s.in_block, {s.in_block.size()});
    out.write(x + "/sum", s.sum, {s.sum.size()});
    out.write(x + "/count", s.count, {s.count.size()});
  }
}

ObserverRows CorrelationsObserver::load(const H5Reader& in, const std::string& g, bool,
                                        std::uint64_t) const {
  const std::string base = g + "/correlations";
  auto malformed = [&](const std::string& why) {
    return std::runtime_error(in.path() + ": malformed ensemble state " + g + ": " + why);
  };
  if (!in.exists(base + "/next_sample")) throw malformed("no correlations in it");
  ObserverRows w;
  w.counts = in.read_uint64(base + "/next_sample");
  if (w.counts.size() != 3) throw malformed("next_sample of the wrong size");
  for (int k = 0; k < 3; ++k)
    if (w.counts[k] > (spec(k).on ? spec(k).samples : 0)) throw malformed("samples beyond t_end");
  for (std::size_t j = 0; j < channels_.size(); ++j) {
    const std::string x = base + "/" + std::to_string(j);
    for (const char* part : {"/shift", "/block", "/fill", "/in_block", "/sum", "/count"})
      if (!in.exists(x + part))
        throw malformed(std::string("no ") + (part + 1) + " of correlator " + std::to_string(j));
    MultipleTauCorrelator::State s;
    s.shift = in.read_double(x + "/shift");
    s.block = in.read_double(x + "/block");
    s.fill = in.read_uint64(x + "/fill");
    s.in_block = in.read_uint64(x + "/in_block");
    s.sum = in.read_double(x + "/sum");
    s.count = in.read_uint64(x + "/count");
    try {
      w.correlators.emplace_back(channels_[j].width, resolution(channels_[j].spec), std::move(s));
    } catch (const std::invalid_argument& e) {
      throw malformed(e.what());
    }
  }
  return w;
}

void CorrelationsObserver::accumulate(const FinishedEnsemble& f, const ObserverRows& w,
                                      Record& record) const {
  for (std::size_t j = 0; j < channels_.size(); ++j) {
    const Channel& ch = channels_[j];
    const std::vector<double> c = w.correlators[j].correlation();
    for (const double x : c)
      if (!std::isfinite(x))
        throw std::runtime_error("dsmc: ensemble " + std::to_string(f.index) + ": the " +
                                 ch.path.substr(14) + " correlation is not finite at every lag");
    // Normalised by its own lag 0; a signal that vanishes (no particle moves) correlates as 0.
    std::vector<double> rho(c.size(), 0.0);
    if (c[0] > 0)
      for (std::size_t l = 0; l < c.size(); ++l) rho[l] = c[l] / c[0];
    auto& mean = record.moments(ch.key);
    auto& cross = record.moments(ch.key + "_cross");
    for (std::size_t l = 0, q = 0; l < rho.size(); ++l) {
      mean[l].add(rho[l]);
      for (std::size_t k = l; k < rho.size(); ++k, ++q) cross[q].sum.add(rho[l] * rho[k]);
    }
    record.moments(ch.key + "_lag0")[0].add(c[0]);
  }
}

void CorrelationsObserver::present(Presenter& out, const Record& record) const {
  const std::uint64_t N = record.ensembles();
  for (const Channel& ch : channels_) {
    const CorrelationSpec& x = spec(ch.spec);
    const MultipleTauCorrelator::Resolution r = resolution(ch.spec);
    const std::uint64_t L = MultipleTauCorrelator::lag_count(r);
    const std::vector<std::uint64_t> lag_samples = MultipleTauCorrelator(1, r).lags();
    std::vector<double> lag(L), mean(L), ci(L), cov(L * L);
    const auto& sums = record.moments(ch.key);
    const auto& cross = record.moments(ch.key + "_cross");
    for (std::uint64_t l = 0; l < L; ++l) {
      lag[l] = static_cast<double>(lag_samples[l]) * x.every;
      const MeanCi s = sums[l].stats(N);
      mean[l] = s.mean;
      ci[l] = s.ci;
    }
    // The sample covariance of rho over the ensembles (N - 1), as numpy.cov.
    const double Nd = static_cast<double>(N);
    for (std::uint64_t l = 0, q = 0; l < L; ++l)
      for (std::uint64_t k = l; k < L; ++k, ++q) {
        const double v = N < 2 ? std::numeric_limits<double>::quiet_NaN()
                               : (cross[q].sum.value() - Nd * mean[l] * mean[k]) / (Nd - 1.0);
        cov[l * L + k] = cov[k * L + l] = v;
      }
    const MeanCi zero = record.moments(ch.key + "_lag0")[0].stats(N);
    const std::string what =
        ch.signal == kVelocity ? "the velocity autocorrelation of the tagged particles"
        : ch.signal == kStress ? "the autocorrelation of the shear stress sum m c_a c_b / sqrt(n)"
        : ch.signal == kNormalStress
            ? "the autocorrelation of the normal-stress differences sum m (c_a^2 - c_b^2) / (2 "
              "sqrt(n))"
            : "the autocorrelation of the heat flux sum c (m |c|^2 / 2 - (d + 2) T / 2) / sqrt(n)";
    const Dims l1{L};
    out.write(ch.path + "/lag", lag, l1, "the lags (time) of " + what);
    out.write(ch.path + "/mean", mean, l1,
              what + " normalised by its value at lag 0 in each ensemble: mean over the ensembles");
    out.write(ch.path + "/ci", ci, l1, what + ", normalised: confidence half-width of the mean");
    out.write(ch.path + "/covariance", cov, {L, L},
              what + ", normalised: covariance of the ensembles' values between lags (N - 1)");
    out.write(ch.path + "/lag0", std::vector<double>{zero.mean}, {},
              what + " at lag 0 (mean over channels and origins): mean over the ensembles");
    out.write(ch.path + "/lag0_ci", std::vector<double>{zero.ci}, {},
              what + " at lag 0: confidence half-width");
    out.attr(ch.path, "description", what);
    out.attr(ch.path, "every", x.every);
    out.attr(ch.path, "from", x.from);
    out.attr(ch.path, "points", std::uint64_t{x.points});
    out.attr(ch.path, "averaging", std::uint64_t{x.averaging});
    out.attr(ch.path, "levels", std::uint64_t{x.levels});
    out.attr(ch.path, "channels", ch.width);
    out.attr(ch.path, "samples", x.samples);
  }
}

}  // namespace granboltz
