// dsmc.correlations: which time correlations a run samples, and how finely.
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "granboltz/config/reader.hpp"
#include "granboltz/dsmc/config.hpp"
#include "granboltz/stats/correlator.hpp"

namespace granboltz {

namespace {

constexpr const char* kNames[] = {"velocity", "stress", "heat_flux"};
constexpr double kPi = 3.14159265358979323846;
// Samples per mean free time by default: the correlations of a dilute gas decay over a few.
constexpr double kSamplesPerCollision = 10.0;
// Tagged particles per species by default: their velocities are the correlator's channels,
// whose cost per sample grows with their number (bench/correlations.yaml).
constexpr std::uint64_t kDefaultTagged = 256;

CorrelationSpec* spec(CorrelationsSpec& c, int k) {
  return k == 0 ? &c.velocity : k == 1 ? &c.stress : &c.heat_flux;
}
const CorrelationSpec* spec(const CorrelationsSpec& c, int k) {
  return k == 0 ? &c.velocity : k == 1 ? &c.stress : &c.heat_flux;
}

// The collision frequency of a unit-mass particle in a Maxwellian gas at temperature T:
// |S^(d-1)| gamma C E|u|^lambda, with E|u|^lambda = (4T)^(lambda/2) Gamma((d+lambda)/2)/Gamma(d/2)
// for the relative velocity of two such particles.
double collision_frequency(const DsmcConfig& c, double T) {
  const double d = c.dimension, lambda = c.kernel.lambda;
  const double sphere = c.dimension == 2 ? 2.0 * kPi : 4.0 * kPi;
  const double mean = std::pow(4.0 * T, lambda / 2.0) *
                      std::exp(std::lgamma((d + lambda) / 2.0) - std::lgamma(d / 2.0));
  return sphere * c.kernel.gamma * c.kernel.C * mean;
}

std::uint64_t smallest_species(const DsmcConfig& c) {
  if (c.species.empty()) return c.particles;
  std::uint64_t n = c.particles;
  for (const auto& sp : c.species) n = std::min(n, sp.count);
  return n;
}

void read_one(const Section& o, int k, const DsmcConfig& c, CorrelationSpec& x) {
  x.on = true;
  const double span_end = c.t_end;
  x.from = o.real("from", c.steady ? c.steady_from : 0.0);
  o.check(x.from >= 0 && x.from < span_end, "from", x.from,
          "must satisfy 0 <= from < t_end = " + format_real(span_end));
  const double nu = collision_frequency(c, c.initial_temperature);
  const double every_default = nu > 0 && std::isfinite(nu) ? 1.0 / (kSamplesPerCollision * nu)
                                                           : (span_end - x.from) / 1000.0;
  x.every = o.real("every", every_default);
  o.check(x.every > 0 && x.every <= span_end - x.from, "every", x.every,
          "must satisfy 0 < every <= t_end - from = " + format_real(span_end - x.from));
  const double samples = std::floor((span_end - x.from) / x.every * (1.0 + 1e-12)) + 1.0;
  o.check(samples <= 1e9, "every", x.every,
          "gives more than 10^9 samples from " + format_real(x.from) + " to t_end");
  x.samples = static_cast<std::uint64_t>(samples);
  x.points = static_cast<unsigned>(
      o.integer("points", 16, {2, 1024, "must be even and satisfy 2 <= points <= 1024"}));
  o.check(x.points % 2 == 0, "points", x.points, "must be even and satisfy 2 <= points <= 1024");
  x.averaging = static_cast<unsigned>(o.integer(
      "averaging", 2, {2, 1024, "must satisfy 2 <= averaging <= points and divide points"}));
  o.check(x.averaging <= x.points && x.points % x.averaging == 0, "averaging", x.averaging,
          "must satisfy 2 <= averaging <= points = " + std::to_string(x.points) + " and divide it");
  o.check(x.points <= x.samples, "every", x.every,
          "gives " + std::to_string(x.samples) + " samples from " + format_real(x.from) +
              " to t_end, fewer than points = " + std::to_string(x.points));
  // The longest lag of level K needs points m^(K-1) samples; by default the levels reach as far
  // as half the samples allow, so that every lag has at least half the run's time origins.
  const auto reach = [&](std::uint64_t K) {
    return static_cast<double>(x.points) * std::pow(double(x.averaging), double(K) - 1.0);
  };
  if (o.has("levels")) {
    x.levels =
        static_cast<unsigned>(o.integer("levels", {1, 60, "must satisfy 1 <= levels <= 60"}));
    o.check(reach(x.levels) <= static_cast<double>(x.samples), "levels", x.levels,
            "reaches lags beyond the " + std::to_string(x.samples) + " samples from " +
                format_real(x.from) +
                " to t_end (points averaging^(levels-1) must not exceed them)");
  } else {
    x.levels = 1;
    while (x.levels < 60 && reach(x.levels + 1) <= 0.5 * static_cast<double>(x.samples)) ++x.levels;
  }
  MultipleTauCorrelator::check({x.points, x.averaging, x.levels});
  std::vector<std::string> keys = {"every", "from", "points", "averaging", "levels"};
  if (k == 0) {
    const std::uint64_t fewest = smallest_species(c);
    x.particles =
        o.integer("particles", std::min(kDefaultTagged, fewest),
                  {1, fewest,
                   "must satisfy 1 <= particles <= " + std::to_string(fewest) +
                       (c.species_written ? " (the smallest species)" : " (dsmc.particles)")});
    keys.push_back("particles");
  }
  o.finish(keys);
}

}  // namespace

double CorrelationsSpec::next_after(double after, double t_end) const {
  double best = std::numeric_limits<double>::infinity();
  for (const CorrelationSpec* x : {&velocity, &stress, &heat_flux}) {
    if (!x->on) continue;
    // The same times as the run's own count k = 0, 1, ...: start a little before and step on.
    std::uint64_t k = 0;
    if (after > x->from) k = static_cast<std::uint64_t>(std::floor((after - x->from) / x->every));
    k = k > 0 ? k - 1 : 0;
    while (k < x->samples && !(x->time(k, t_end) > after)) ++k;
    if (k < x->samples) best = std::min(best, x->time(k, t_end));
  }
  return best;
}

void read_correlations(const Section& s, DsmcConfig& c) {
  const Section o = s.sub("correlations");
  o.finish({kNames[0], kNames[1], kNames[2]});
  if (!o.has(kNames[0]) && !o.has(kNames[1]) && !o.has(kNames[2]))
    throw ConfigError(s.name("correlations") +
                      ": names none of velocity, stress, heat_flux (each a mapping; {} takes "
                      "the defaults)");
  // Where a correlation cannot be sampled exactly, one line naming the key.
  if (c.weights.swpm)
    throw ConfigError(s.name("correlations") +
                      ": not available with dsmc.weights (weighted "
                      "particles are split and merged: none keeps its identity)");
  if (c.scheme != Scheme::kNoSplit)
    throw ConfigError(s.name("correlations") +
                      ": needs scheme nosplit (the splitting schemes "
                      "advance in whole time steps, the samples fall between them)");
  for (int k = 0; k < 3; ++k)
    if (o.has(kNames[k])) read_one(o.sub(kNames[k]), k, c, *spec(c.correlations, k));
}

void emit_correlations(YAML::Emitter& out, const DsmcConfig& c) {
  if (!c.correlations.any()) return;
  out << YAML::Key << "correlations" << YAML::Value << YAML::BeginMap;
  for (int k = 0; k < 3; ++k) {
    const CorrelationSpec& x = *spec(c.correlations, k);
    if (!x.on) continue;
    out << YAML::Key << kNames[k] << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key
        << "every" << YAML::Value << format_real(x.every) << YAML::Key << "from" << YAML::Value
        << format_real(x.from) << YAML::Key << "points" << YAML::Value << x.points << YAML::Key
        << "averaging" << YAML::Value << x.averaging << YAML::Key << "levels" << YAML::Value
        << x.levels;
    if (k == 0) out << YAML::Key << "particles" << YAML::Value << x.particles;
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
}

}  // namespace granboltz
