// The `intruder:` and `needle:` sections: reading, validation and emission.
#include "granboltz/tv06/config.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "granboltz/config/reader.hpp"

namespace granboltz {

namespace {

VelocityHistogramSpec read_histogram(const Section& s, const std::string& key) {
  VelocityHistogramSpec h;
  if (!s.has(key)) return h;
  const Section hs = s.sub(key);
  h.bins = hs.integer("bins", {1, 10'000'000, "must satisfy 1 <= bins <= 10^7"});
  h.range = hs.real("range");
  hs.check(h.range > 0, "range", h.range, "must be > 0");
  // The bins span 2 range: beyond about 9e307 that overflows and the edges become infinite.
  hs.check(h.range <= 1e300, "range", h.range, "must satisfy 0 < range <= 1e300");
  hs.finish({"bins", "range"});
  return h;
}

void emit_histogram(YAML::Emitter& out, const char* key, const VelocityHistogramSpec& h) {
  if (h.bins == 0) return;
  out << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "bins"
      << YAML::Value << h.bins << YAML::Key << "range" << YAML::Value << format_real(h.range)
      << YAML::EndMap;
}

void read_common(const Section& s, double& alpha, double& density, std::uint64_t& collisions,
                 double& sample_every, std::uint64_t& warmup) {
  alpha = s.real("alpha");
  s.check(alpha >= 0 && alpha <= 1, "alpha", alpha, "must satisfy 0 <= alpha <= 1");
  density = s.real("density", 1.0);
  s.check(density > 0, "density", density, "must be > 0");
  collisions = s.integer("collisions", {1, kMaxInteger, "must be >= 1"});
  sample_every = s.real("sample_every", 0.0);
  s.check(sample_every >= 0, "sample_every", sample_every, "must be >= 0 (0: mean free time)");
  warmup = s.integer("warmup", collisions / 10);
}

/// The needle is simulated in the config's units, so its scales must stay far from the ends of
/// double precision: beyond these bounds I, 1/M, the rates or the waiting times over- or
/// underflow (the run would produce NaN and loop forever). Inside them every waiting-time
/// method works (ρ L² is the parameter that matters: tiny L rotates many turns per collision).
void check_needle_scales(const Section& s, const NeedleConfig& c) {
  char here[64];
  s.check(c.mass >= 1e-300, "mass", c.mass, "must be >= 1e-300 (1/M and the speeds overflow)");
  s.check(c.a >= 1e-100 && c.a <= 1e100, "a", c.a,
          "must satisfy 1e-100 <= a <= 1e100 (T_B = 1/(2a) and its powers over/underflow)");
  const double inertia = c.mass * c.length * c.length / 12.0;
  std::snprintf(here, sizeof here, " (here %.3g)", inertia);
  s.check(inertia >= 1e-300 && inertia <= 1e300, "length", c.length,
          "must give a moment of inertia 1e-300 <= M L^2/12 <= 1e300" + std::string(here));
  // Phi(0, 0) = rho L / sqrt(pi a); at thermal speeds the rate is at most ~ (1 + 5/sqrt(M)) times
  // it.
  const double rate = c.density * c.length / std::sqrt(M_PI * c.a);
  const double fastest = rate * (1.0 + 5.0 / std::sqrt(c.mass));
  std::snprintf(here, sizeof here, " (here %.3g)", rate);
  s.check(rate >= 1e-250, "density", c.density,
          "must give a rate rho L/sqrt(pi a) >= 1e-250" + std::string(here));
  std::snprintf(here, sizeof here, " (here %.3g)", fastest);
  s.check(fastest <= 1e250, "density", c.density,
          "must give a rate (1 + 5/sqrt(M)) rho L/sqrt(pi a) <= 1e250" + std::string(here));
}

}  // namespace

IntruderConfig read_intruder(const Section& s) {
  IntruderConfig c;
  const Section b = s.sub("bath");
  if (!s.has("bath")) throw ConfigError(s.name("bath") + ": missing (required)");
  c.bath.kind = b.choice("kind", {"gaussian", "powerlaw"}) == "powerlaw" ? BathKind::kPowerLaw
                                                                         : BathKind::kGaussian;
  c.bath.a = b.real("a");
  b.check(c.bath.a > 0, "a", c.bath.a, "must be > 0");
  b.finish({"kind", "a"});
  c.mass = s.real("mass");
  s.check(c.mass > 0, "mass", c.mass, "must be > 0");
  read_common(s, c.alpha, c.density, c.collisions, c.sample_every, c.warmup);
  c.method = s.choice("method", {"gillespie", "dsmc"}, "gillespie") == "dsmc"
                 ? IntruderMethod::kDsmc
                 : IntruderMethod::kGillespie;
  c.bath_particles = s.integer("bath_particles", 1000, {1, kMaxInteger, "must be >= 1"});
  const std::string refresh = s.choice("bath_refresh", {"tested", "collided", "none"}, "tested");
  c.bath_refresh = refresh == "collided" ? BathRefresh::kCollided
                   : refresh == "none"   ? BathRefresh::kNone
                                         : BathRefresh::kTested;
  c.histogram = read_histogram(s, "histogram");
  s.finish({"bath", "mass", "alpha", "density", "collisions", "method", "sample_every", "warmup",
            "bath_particles", "bath_refresh", "histogram"});
  return c;
}

NeedleConfig read_needle(const Section& s) {
  NeedleConfig c;
  c.mass = s.real("mass");
  s.check(c.mass > 0, "mass", c.mass, "must be > 0");
  c.length = s.real("length", 1.0);
  s.check(c.length > 0, "length", c.length, "must be > 0");
  c.a = s.real("a", 1.0);
  s.check(c.a > 0, "a", c.a, "must be > 0");
  read_common(s, c.alpha, c.density, c.collisions, c.sample_every, c.warmup);
  c.waiting_time = s.choice("waiting_time", {"thinning", "inversion"}, "thinning") == "inversion"
                       ? NeedleWaitingTime::kInversion
                       : NeedleWaitingTime::kThinning;
  check_needle_scales(s, c);
  c.velocity_histogram = read_histogram(s, "velocity_histogram");
  c.omega_histogram = read_histogram(s, "omega_histogram");
  s.finish({"mass", "length", "alpha", "a", "density", "collisions", "sample_every", "warmup",
            "waiting_time", "velocity_histogram", "omega_histogram"});
  return c;
}

void emit_intruder(YAML::Emitter& out, const IntruderConfig& c) {
  out << YAML::Key << "intruder" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "bath" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "kind"
      << YAML::Value << (c.bath.kind == BathKind::kPowerLaw ? "powerlaw" : "gaussian") << YAML::Key
      << "a" << YAML::Value << format_real(c.bath.a) << YAML::EndMap;
  out << YAML::Key << "mass" << YAML::Value << format_real(c.mass);
  out << YAML::Key << "alpha" << YAML::Value << format_real(c.alpha);
  out << YAML::Key << "density" << YAML::Value << format_real(c.density);
  out << YAML::Key << "collisions" << YAML::Value << c.collisions;
  out << YAML::Key << "method" << YAML::Value
      << (c.method == IntruderMethod::kDsmc ? "dsmc" : "gillespie");
  out << YAML::Key << "sample_every" << YAML::Value << format_real(c.sample_every);
  out << YAML::Key << "warmup" << YAML::Value << c.warmup;
  if (c.method == IntruderMethod::kDsmc) {
    out << YAML::Key << "bath_particles" << YAML::Value << c.bath_particles;
    out << YAML::Key << "bath_refresh" << YAML::Value
        << (c.bath_refresh == BathRefresh::kCollided ? "collided"
            : c.bath_refresh == BathRefresh::kNone   ? "none"
                                                     : "tested");
  }
  emit_histogram(out, "histogram", c.histogram);
  out << YAML::EndMap;
}

void emit_needle(YAML::Emitter& out, const NeedleConfig& c) {
  out << YAML::Key << "needle" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "mass" << YAML::Value << format_real(c.mass);
  out << YAML::Key << "length" << YAML::Value << format_real(c.length);
  out << YAML::Key << "alpha" << YAML::Value << format_real(c.alpha);
  out << YAML::Key << "a" << YAML::Value << format_real(c.a);
  out << YAML::Key << "density" << YAML::Value << format_real(c.density);
  out << YAML::Key << "collisions" << YAML::Value << c.collisions;
  out << YAML::Key << "sample_every" << YAML::Value << format_real(c.sample_every);
  out << YAML::Key << "warmup" << YAML::Value << c.warmup;
  out << YAML::Key << "waiting_time" << YAML::Value
      << (c.waiting_time == NeedleWaitingTime::kInversion ? "inversion" : "thinning");
  emit_histogram(out, "velocity_histogram", c.velocity_histogram);
  emit_histogram(out, "omega_histogram", c.omega_histogram);
  out << YAML::EndMap;
}

}  // namespace granboltz
