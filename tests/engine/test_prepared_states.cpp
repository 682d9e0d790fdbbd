// Prepared initial states (dsmc.initial): the anisotropic Maxwellian of a temperature tensor and
// the exact relaxation of its pressure anisotropy for Maxwell molecules (lambda = 0).
//
// Exact result (docs/physics.md, "Prepared states"): for lambda = 0 with e uniform on S^{d-1}
// every pair collides at the same rate, so the expectation of the centred second-moment tensor
// C = (1/n) sum (v - V)(v - V)^T of the n-particle system obeys a closed linear equation,
//   dE[C]/dt = (nu/2) [ (4a^2 - 1) E[C] + (4b^2/d) tr E[C] I ],  a = (1-alpha)/4, b = (1+alpha)/4,
// nu = |S^{d-1}| gamma C per particle, with no finite-n correction (the pair rate's factor
// (n - 1)/n and the pair average's n/(n - 1) cancel). Its traceless part Pi decays at
// r_Pi = nu (1+alpha)(3-alpha)/8 and its trace at zeta = nu (1 - alpha^2)/4, in d = 2 and 3, and
// E[C(0)] = (1 - 1/n) T_ij for n independent draws. The Gaussian thermostat holds T and leaves
// Pi/p unchanged, so there Pi decays at r_Pi - zeta = nu (1+alpha)^2/8, up to the O(1/n) bias of
// the ratio of sums (about 1/n relative, 1/50 of the half-widths below).
//
// The heat flux q = (1/2) <c |c|^2> of a skewed start (dsmc.initial.heat_flux) closes the same
// way at third order (the mixed pair terms reduce to -q/(n-1) exactly, since sum c_i = 0, and
// cancel the pair rate's factor again): E[q(t)] = (1 - 1/n)(1 - 2/n) q0 e^{-nu_q t},
// nu_q = nu (1 - p^3 - q^3 - b^2 (d+2)/d), p = (3-alpha)/4, q = b = (1+alpha)/4, i.e.
// nu (1+alpha)(11-7alpha)/24 in d = 3 and nu (1+alpha)(7-5alpha)/16 in d = 2; under the Gaussian
// thermostat q/T^{3/2} decays at nu_q - 3 zeta/2: nu (1+alpha)^2/12 (d = 3), nu (1+alpha)^2/16
// (d = 2), again to O(1/n).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "granboltz/dsmc/run.hpp"
#include "test_support.hpp"

using namespace granboltz;

namespace {

constexpr int kPressure = 5, kHeatFlux = 14;

struct Prepared {
  int d = 3;
  std::vector<double> T;  // d x d
  double alpha = 0.5;
  std::string thermostat = "none";
};

std::string matrix_text(const std::vector<double>& T, int d) {
  std::string s = "[";
  for (int a = 0; a < d; ++a) {
    s += a ? ", [" : "[";
    for (int b = 0; b < d; ++b) s += (b ? ", " : "") + format_real(T[a * d + b]);
    s += "]";
  }
  return s + "]";
}

Config prepared_config(const Prepared& k, std::uint64_t n, std::uint64_t N, std::uint64_t seed,
                       const std::vector<std::string>& extra = {}) {
  // nu = |S^{d-1}| gamma C = 1.
  const double C = k.d == 3 ? 1 / (4 * M_PI) : 1 / (2 * M_PI);
  std::vector<std::string> sets = {"model=dsmc",
                                   "seed=" + std::to_string(seed),
                                   "ensembles=" + std::to_string(N),
                                   "dsmc.particles=" + std::to_string(n),
                                   "dsmc.dimension=" + std::to_string(k.d),
                                   "dsmc.geometry=uniform",
                                   "dsmc.alpha=" + format_real(k.alpha),
                                   "dsmc.beta=0",
                                   "dsmc.thermostat=" + k.thermostat,
                                   "dsmc.gamma=1",
                                   "dsmc.kernel.lambda=0",
                                   "dsmc.kernel.C=" + format_real(C),
                                   "dsmc.t_end=4",
                                   "dsmc.observe_every=0.5"};
  if (!k.T.empty()) sets.push_back("dsmc.initial.temperature=" + matrix_text(k.T, k.d));
  sets.insert(sets.end(), extra.begin(), extra.end());
  return parse_config("{}", "test", sets);
}

/// E[P_ab(t)] of the exact linear equation above.
double exact_pressure(const Prepared& k, double n, int a, int b, double t) {
  const double nu = 1.0, al = k.alpha;
  const double r_pi = nu * (1 + al) * (3 - al) / 8, zeta = nu * (1 - al * al) / 4;
  double T0 = 0.0;
  for (int i = 0; i < k.d; ++i) T0 += k.T[i * k.d + i] / k.d;
  const double pi0 = k.T[a * k.d + b] - (a == b ? T0 : 0.0);
  if (k.thermostat == "gaussian")  // T held at T0 (the fold makes it exact), Pi/p relaxes
    return (a == b ? T0 : 0.0) + pi0 * std::exp(-(r_pi - zeta) * t);
  return (1 - 1 / n) * ((a == b ? T0 * std::exp(-zeta * t) : 0.0) + pi0 * std::exp(-r_pi * t));
}

void expect_relaxation(const Prepared& k, std::uint64_t n, std::uint64_t N, std::uint64_t seed,
                       const std::vector<std::string>& extra = {}) {
  const test::DsmcRun r(prepared_config(k, n, N, seed, extra));
  const int comps = k.d * (k.d + 1) / 2;
  const double z = test::family_z(static_cast<int>(r.times.size()) * comps);
  for (std::size_t m = 0; m < r.times.size(); ++m)
    for (int a = 0; a < k.d; ++a)
      for (int b = a; b < k.d; ++b) {
        const MeanCi P = r.at(m, kPressure + 3 * a + b);
        const double expected = exact_pressure(k, static_cast<double>(n), a, b, r.times[m]);
        EXPECT_NEAR(P.mean, expected, z * std::sqrt(P.variance / static_cast<double>(N)))
            << "P_" << a << b << " t=" << r.times[m] << " d=" << k.d << " " << k.thermostat;
      }
}

/// The exact rate of the heat flux (nu = 1), free cooling or (gaussian) of q/T^{3/2}.
double heat_flux_rate(int d, double al, bool gaussian) {
  const double p = (3 - al) / 4, b = (1 + al) / 4;
  const double free = 1 - p * p * p - b * b * b - b * b * (d + 2.0) / d;
  return gaussian ? free - 1.5 * (1 - al * al) / 4 : free;
}

void expect_heat_flux_relaxation(const Prepared& k, const std::vector<double>& q0, std::uint64_t n,
                                 std::uint64_t N, std::uint64_t seed) {
  std::string q = "[";
  for (int a = 0; a < k.d; ++a) q += (a ? ", " : "") + format_real(q0[a]);
  const test::DsmcRun r(prepared_config(k, n, N, seed, {"dsmc.initial.heat_flux=" + q + "]"}));
  const bool gaussian = k.thermostat == "gaussian";
  const double rate = heat_flux_rate(k.d, k.alpha, gaussian), nn = static_cast<double>(n);
  // E[q(0)] of the centred sample (third central moment); with the Gaussian fold the leading
  // factor of E[q/T^{3/2}] T0^{3/2}.
  const double start =
      gaussian ? (1 - 2 / nn) / std::sqrt(1 - 1 / nn) : (1 - 1 / nn) * (1 - 2 / nn);
  const double z = test::family_z(static_cast<int>(r.times.size()) * k.d);
  for (std::size_t m = 0; m < r.times.size(); ++m)
    for (int a = 0; a < k.d; ++a) {
      const MeanCi Q = r.at(m, kHeatFlux + a);
      EXPECT_NEAR(Q.mean, start * q0[a] * std::exp(-rate * r.times[m]),
                  z * std::sqrt(Q.variance / static_cast<double>(N)))
          << "q_" << a << " t=" << r.times[m] << " d=" << k.d << " " << k.thermostat;
    }
}

const std::vector<double> kT3 = {1.3, 0.4, 0.0, 0.4, 0.9, 0.1, 0.0, 0.1, 0.8};
const std::vector<double> kT2 = {1.4, -0.3, -0.3, 0.6};

}  // namespace

TEST(PreparedStates, AnisotropicMaxwellianHasItsTemperatureTensor) {
  // t = 0 rows of each engine: E[C(0)] = (1 - 1/n) T exactly (the Gaussian fold rescales to the
  // trace, so the free gas is checked); one species, the general gas, weighted particles.
  const Prepared k{3, kT3};
  const std::vector<std::vector<std::string>> engines = {
      {},
      {"dsmc.species=[{name: a, fraction: 0.5}, {name: b, fraction: 0.5}]"},
      {"dsmc.weights.method=swpm", "dsmc.weights.kappa=0", "dsmc.weights.max_particles=4000"}};
  std::uint64_t seed = 40;
  for (const auto& extra : engines) {
    std::vector<std::string> sets = extra;
    sets.push_back("dsmc.t_end=0.5");
    const test::DsmcRun r(prepared_config(k, 500, 200, ++seed, sets));
    const double z = test::family_z(3 * 6);
    for (int a = 0; a < 3; ++a)
      for (int b = a; b < 3; ++b) {
        const MeanCi P = r.at(0, kPressure + 3 * a + b);
        EXPECT_NEAR(P.mean, (1 - 1.0 / 500) * kT3[3 * a + b], z * std::sqrt(P.variance / 200))
            << "P_" << a << b << " engine " << (extra.empty() ? "one species" : extra[0]);
      }
  }
}

TEST(PreparedStates, PressureAnisotropyRelaxesAtTheExactMaxwellRate) {
  expect_relaxation({3, kT3, 0.5, "none"}, 1000, 400, 1);
  expect_relaxation({3, kT3, 0.8, "none"}, 1000, 400, 2);
  expect_relaxation({2, kT2, 0.5, "none"}, 1000, 400, 3);
}

TEST(PreparedStates, PressureAnisotropyRelaxesUnderTheGaussianThermostat) {
  expect_relaxation({3, kT3, 0.5, "gaussian"}, 2000, 300, 4);
  expect_relaxation({2, kT2, 0.3, "gaussian"}, 2000, 300, 5);
}

TEST(PreparedStates, GeneralGasRelaxesAtTheSameRate) {
  // Two species of equal mass, size and alpha are one gas: the general engine's Pi decays at
  // the one-species rate.
  expect_relaxation({3, kT3, 0.5, "none"}, 1000, 300, 6,
                    {"dsmc.species=[{name: a, fraction: 0.5}, {name: b, fraction: 0.5}]"});
}

TEST(PreparedStates, TemperatureMatrixIsCheckedAndStoredOnlyWhenWritten) {
  const std::vector<std::string> base = {"model=dsmc",           "seed=1",          "ensembles=1",
                                         "dsmc.particles=10",    "dsmc.alpha=0.5",  "dsmc.beta=0",
                                         "dsmc.kernel.lambda=0", "dsmc.kernel.C=1", "dsmc.t_end=1"};
  auto with = [&](const std::string& set) {
    auto sets = base;
    sets.push_back(set);
    return sets;
  };
  const Config iso = parse_config("{}", "t", with("dsmc.initial.temperature=0.7"));
  EXPECT_TRUE(iso.dsmc.initial_temperature_tensor.empty());
  EXPECT_NE(iso.to_yaml(true).find("temperature: 0.7"), std::string::npos);
  const Config an = prepared_config({3, kT3}, 10, 1, 1);
  EXPECT_DOUBLE_EQ(an.dsmc.initial_temperature, 1.0);
  // The stored config reads back to the same tensor.
  const Config again = parse_config(an.to_yaml(true), "t", {});
  EXPECT_EQ(again.dsmc.initial_temperature_tensor, kT3);
  auto refused = [&](const std::string& value, const std::string& part) {
    try {
      parse_config("{}", "t", with("dsmc.initial.temperature=" + value));
      ADD_FAILURE() << value << " accepted";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
  };
  refused("[[1, 0.1, 0], [0, 1, 0], [0, 0, 1]]", "symmetric");
  refused("[[1, 2, 0], [2, 1, 0], [0, 0, 1]]", "positive definite");
  refused("[[1, 0], [0, 1]]", "3 x 3");
  refused("[[1, 0, 0], [0, 1, 0], [0, 0, .nan]]", "temperature[2][2]");
}

TEST(PreparedStates, HeatFluxRelaxesAtTheExactMaxwellRate) {
  // alpha = 0.8: nu_q = 0.405 against nu_Pi = 0.495 (at alpha = 1/2 the two coincide).
  expect_heat_flux_relaxation({3, {}, 0.8, "none"}, {0.12, -0.08, 0.05}, 2000, 1000, 11);
  expect_heat_flux_relaxation({2, {}, 0.8, "none"}, {0.2, 0.15}, 2000, 1000, 12);
}

TEST(PreparedStates, HeatFluxRelaxesUnderTheGaussianThermostat) {
  expect_heat_flux_relaxation({3, {}, 0.5, "gaussian"}, {0.15, 0.0, -0.1}, 2000, 1000, 13);
  expect_heat_flux_relaxation({2, {}, 0.5, "gaussian"}, {-0.2, 0.1}, 2000, 1000, 14);
}

TEST(PreparedStates, SkewedStateHasItsHeatFluxAndMaxwellianEvenMoments) {
  // t = 0 rows of each engine: E[q(0)] = (1 - 1/n)(1 - 2/n) q, E[P(0)] = (1 - 1/n) T0 I.
  const std::vector<std::vector<std::string>> engines = {
      {},
      {"dsmc.species=[{name: a, fraction: 0.5}, {name: b, fraction: 0.5}]"},
      {"dsmc.weights.method=swpm", "dsmc.weights.kappa=0", "dsmc.weights.max_particles=4000"}};
  const double q0[3] = {0.15, -0.1, 0.05}, n = 500, N = 400;
  std::uint64_t seed = 60;
  for (const auto& extra : engines) {
    std::vector<std::string> sets = extra;
    sets.push_back("dsmc.t_end=0.5");
    sets.push_back("dsmc.initial.heat_flux=[0.15, -0.1, 0.05]");
    const test::DsmcRun r(prepared_config({3, {}}, 500, 400, ++seed, sets));
    const double z = test::family_z(3 * 9);
    for (int a = 0; a < 3; ++a) {
      const MeanCi Q = r.at(0, kHeatFlux + a);
      EXPECT_NEAR(Q.mean, (1 - 1 / n) * (1 - 2 / n) * q0[a], z * std::sqrt(Q.variance / N))
          << "q_" << a << " engine " << (extra.empty() ? "one species" : extra[0]);
      for (int b = a; b < 3; ++b) {
        const MeanCi P = r.at(0, kPressure + 3 * a + b);
        EXPECT_NEAR(P.mean, a == b ? 1 - 1 / n : 0.0, z * std::sqrt(P.variance / N))
            << "P_" << a << b << " engine " << (extra.empty() ? "one species" : extra[0]);
      }
    }
  }
}

TEST(PreparedStates, HeatFluxBeyondAPositiveDensityIsRefused) {
  const std::vector<std::string> base = {"model=dsmc",           "seed=1",          "ensembles=1",
                                         "dsmc.particles=10",    "dsmc.alpha=0.5",  "dsmc.beta=0",
                                         "dsmc.kernel.lambda=0", "dsmc.kernel.C=1", "dsmc.t_end=1"};
  auto message = [&](std::vector<std::string> sets) -> std::string {
    sets.insert(sets.begin(), base.begin(), base.end());
    try {
      parse_config("{}", "t", sets);
    } catch (const ConfigError& e) {
      return e.what();
    }
    return "accepted";
  };
  // 0.2006 T0^{3/2} in d = 3: at T0 = 1 0.2 is allowed, 0.201 is not; at T0 = 4, 1.6 is.
  EXPECT_EQ(message({"dsmc.initial.heat_flux=[0.2, 0, 0]"}), "accepted");
  EXPECT_NE(message({"dsmc.initial.heat_flux=[0.201, 0, 0]"}).find("must be < 0.2006"),
            std::string::npos);
  EXPECT_EQ(message({"dsmc.initial.temperature=4", "dsmc.initial.heat_flux=[0, 1.6, 0]"}),
            "accepted");
  EXPECT_NE(message({"dsmc.initial.heat_flux=[0.1, 0]"}).find("list of 3 numbers"),
            std::string::npos);
  EXPECT_NE(message({"dsmc.initial.temperature=[[1, 0, 0], [0, 1, 0], [0, 0, 1]]",
                     "dsmc.initial.heat_flux=[0.1, 0, 0]"})
                .find("needs a number for initial.temperature"),
            std::string::npos);
  EXPECT_NE(message({"dsmc.dimension=2", "dsmc.initial.heat_flux=[0.3, 0.05]"}).find("0.3010"),
            std::string::npos);
}
