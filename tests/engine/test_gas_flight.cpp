// Free flights per species in the general gas (dsmc/gas.hpp): white noise of strength beta_a and
// drag gamma_a for each species (dsmc.beta and dsmc.drag.gamma as mappings of species names).
//
// Exact first. For Maxwell molecules (lambda = 0) every pair collides at the same rate
// k_ab = gamma C sigma_ab^{d-1} |S^{d-1}| / n, whatever the velocities, so the expected change of
// a quadratic function of the velocities is again a quadratic function: the expectations of
// S_a = sum_{i in a} |v_i|^2 and Q_ab = M_a . M_b (M_a = sum_{i in a} v_i) obey a closed linear
// system at any finite n (docs/physics.md, "Per-species heating and drag"), and so do the
// species temperatures the output stores, T_a = m_a <|v - V|^2>_a / d about the mixture's centre
// of mass V, which are linear in S and Q. The tests integrate that system (RK4, step 1e-3: its
// error is far below the statistics) and compare every row of T_a(t) and the steady ratio with
// |x - exact| < z sigma, z the family-wise 0.1 % quantile over the checks of a test. Each test
// also checks that its data reject the same system with a 5 % error in the collision rate and
// with the heating or the drag of one species off by a factor 2, so the comparison can fail.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "granboltz/app/config.hpp"
#include "granboltz/dsmc/gas.hpp"
#include "granboltz/h5/hdf5_io.hpp"
#include "test_support.hpp"

using namespace granboltz;
using granboltz::test::run_granboltz;
using granboltz::test::TempDir;

namespace {

// A binary (or K-species) mixture of Maxwell molecules with its per-species flights.
struct Mixture {
  int d = 3;
  bool impact = false;  // d = 2: hard-disk impact directions (chi = 4/3), else uniform (chi = 1)
  double n = 1000, alpha = 0.8, T0 = 1.0, C = 1.0, kgamma = 1.0;
  std::vector<std::string> names{"a", "b"};
  std::vector<double> fraction{0.5, 0.5}, mass{1.0, 4.0}, diameter{1.0, 1.5};
  std::vector<double> beta{0.0, 0.0}, drag{0.0, 0.0};
  std::string scheme = "nosplit";  // or euler, strang with the time step dt
  double dt = 0.0;
  double area() const { return d == 2 ? 2.0 * M_PI : 4.0 * M_PI; }
  double chi() const { return impact ? 4.0 / 3.0 : 1.0; }
};

// Perturbations of the exact system (to show that a test can fail).
struct Perturb {
  double rate = 1.0;               // every k_ab times this
  std::vector<double> beta{1, 1};  // beta_a times this
  std::vector<double> drag{1, 1};  // gamma_a times this
};

// E[T_a(t)] (centred about the mixture's centre of mass) at the times t, species-major:
// out[a][m]. The state is E[S_a] and E[Q_ab]; see the header comment and docs/physics.md.
std::vector<std::vector<double>> exact_temperatures(const Mixture& x, const std::vector<double>& t,
                                                    const Perturb& p = {}) {
  const std::size_t K = x.mass.size();
  std::vector<double> N(K);
  for (std::size_t a = 0; a < K; ++a) N[a] = x.fraction[a] * x.n;
  const double chi = x.chi(), e = x.alpha;
  std::vector<double> beta(K), gam(K);
  for (std::size_t a = 0; a < K; ++a)
    beta[a] = x.beta[a] * p.beta[a], gam[a] = x.drag[a] * p.drag[a];
  auto k_of = [&](std::size_t a, std::size_t b) {
    const double s = 0.5 * (x.diameter[a] + x.diameter[b]);
    return p.rate * x.kgamma * x.C * x.area() * (x.d == 2 ? s : s * s) / x.n;
  };
  // y = (S_0..S_{K-1}, Q_00, Q_01, ..., Q_{K-1,K-1}) with Q stored as a full K x K matrix.
  const std::size_t dim = K + K * K;
  auto S = [&](std::vector<double>& y, std::size_t a) -> double& { return y[a]; };
  auto Q = [&](std::vector<double>& y, std::size_t a, std::size_t b) -> double& {
    return y[K + a * K + b];
  };
  // parts: 1 the collisions, 2 the flights, 3 both (a splitting scheme runs them in turn).
  auto rhs = [&](std::vector<double> y, int parts) {
    std::vector<double> dy(dim, 0.0), L(K * K, 0.0);
    for (std::size_t a = 0; a < K && (parts & 1); ++a)
      for (std::size_t b = a; b < K; ++b) {
        const double k = k_of(a, b);
        if (a == b) {  // unordered pairs of one species: energy loss only, momentum kept
          dy[a] += -k * (1.0 - e * e) * chi / 4.0 * (N[a] * S(y, a) - Q(y, a, a));
          continue;
        }
        const double mab = x.mass[a] / (x.mass[a] + x.mass[b]), mba = 1.0 - mab;
        const double u2 = N[b] * S(y, a) + N[a] * S(y, b) - 2.0 * Q(y, a, b);  // sum |u|^2
        const double second = (1.0 + e) * (1.0 + e) * chi / 2.0 * u2;          // E[g^2] (1+e)^2
        dy[a] += k * (-mba * (1.0 + e) * chi * (N[b] * S(y, a) - Q(y, a, b)) + mba * mba * second);
        dy[b] += k * (mab * (1.0 + e) * chi * (Q(y, a, b) - N[a] * S(y, b)) + mab * mab * second);
        const double eta = (1.0 + e) * chi / 2.0;  // E[Delta v_i] = -mu_ba eta u
        L[a * K + a] += -k * mba * eta * N[b];
        L[a * K + b] += k * mba * eta * N[a];
        L[b * K + a] += k * mab * eta * N[b];
        L[b * K + b] += -k * mab * eta * N[a];
        Q(dy, a, a) += k * mba * mba * second;
        Q(dy, b, b) += k * mab * mab * second;
        Q(dy, a, b) += -k * mab * mba * second;
        Q(dy, b, a) += -k * mab * mba * second;
      }
    for (std::size_t c = 0; c < K; ++c)
      for (std::size_t f = 0; f < K; ++f)
        for (std::size_t g = 0; g < K; ++g)
          Q(dy, c, f) += L[c * K + g] * Q(y, g, f) + L[f * K + g] * Q(y, c, g);
    for (std::size_t a = 0; a < K && (parts & 2);
         ++a) {  // the flights: dv = -gamma_a v dt + sqrt(2 beta_a) dW
      dy[a] += -2.0 * gam[a] * S(y, a) + 2.0 * x.d * beta[a] * N[a];
      for (std::size_t b = 0; b < K; ++b) Q(dy, a, b) += -(gam[a] + gam[b]) * Q(y, a, b);
      Q(dy, a, a) += 2.0 * x.d * beta[a] * N[a];
    }
    return dy;
  };
  std::vector<double> y(dim, 0.0);
  for (std::size_t a = 0; a < K; ++a) S(y, a) = Q(y, a, a) = N[a] * x.d * x.T0 / x.mass[a];
  double mtot = 0.0;
  for (std::size_t a = 0; a < K; ++a) mtot += x.mass[a] * N[a];
  auto temperatures = [&](std::vector<double>& y, std::vector<std::vector<double>>& out) {
    for (std::size_t a = 0; a < K; ++a) {
      // sum_{i in a} |v_i - V|^2 = S_a - 2 V.M_a + N_a |V|^2, V = sum_b (m_b / M) M_b
      double vm = 0.0, vv = 0.0;
      for (std::size_t b = 0; b < K; ++b) {
        vm += x.mass[b] / mtot * Q(y, a, b);
        for (std::size_t c = 0; c < K; ++c)
          vv += x.mass[b] * x.mass[c] / (mtot * mtot) * Q(y, b, c);
      }
      out[a].push_back(x.mass[a] / (N[a] * x.d) * (S(y, a) - 2.0 * vm + N[a] * vv));
    }
  };
  std::vector<std::vector<double>> out(K);
  auto advance = [&](double duration, int parts) {  // RK4, steps of at most 1e-3
    const int steps = static_cast<int>(std::ceil(duration / 1e-3 - 1e-9));
    const double step = duration / steps;
    std::vector<double> z(dim);
    for (int s = 0; s < steps; ++s) {
      const auto k1 = rhs(y, parts);
      for (std::size_t i = 0; i < dim; ++i) z[i] = y[i] + 0.5 * step * k1[i];
      const auto k2 = rhs(z, parts);
      for (std::size_t i = 0; i < dim; ++i) z[i] = y[i] + 0.5 * step * k2[i];
      const auto k3 = rhs(z, parts);
      for (std::size_t i = 0; i < dim; ++i) z[i] = y[i] + step * k3[i];
      const auto k4 = rhs(z, parts);
      for (std::size_t i = 0; i < dim; ++i)
        y[i] += step / 6.0 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
    }
  };
  double now = 0.0;
  for (double target : t) {
    if (x.scheme == "nosplit") {
      if (target > now) advance(target - now, 3);
      now = target;
    }
    // The schemes' expected moments are exact too: each half runs an exact linear map.
    for (; now < target - 1e-9; now += x.dt) {
      if (x.scheme == "euler") {
        advance(x.dt, 1);
        advance(x.dt, 2);
      } else {
        advance(0.5 * x.dt, 1);
        advance(x.dt, 2);
        advance(0.5 * x.dt, 1);
      }
    }
    temperatures(y, out);
  }
  return out;
}

std::string number(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

// The species-keyed mapping of values (or a plain number when `scalar`).
std::string mapping(const Mixture& x, const std::vector<double>& v) {
  std::string s = "{";
  for (std::size_t a = 0; a < v.size(); ++a)
    s += (a ? ", " : "") + x.names[a] + ": " + number(v[a]);
  return s + "}";
}

std::string config_text(const Mixture& x, int seed, int ensembles, double t_end, double every,
                        double steady_from) {
  std::string s = "model: dsmc\nseed: " + std::to_string(seed) +
                  "\nensembles: " + std::to_string(ensembles) +
                  "\ndsmc:\n  particles: " + number(x.n) + "\n  dimension: " + std::to_string(x.d) +
                  "\n  geometry: " + (x.impact ? "impact" : "uniform") + "\n  species:\n";
  for (std::size_t a = 0; a < x.mass.size(); ++a)
    s += "    - {name: " + x.names[a] + ", fraction: " + number(x.fraction[a]) +
         ", mass: " + number(x.mass[a]) + ", diameter: " + number(x.diameter[a]) + "}\n";
  s += "  alpha: " + number(x.alpha) + "\n";
  bool heated = false;
  for (double b : x.beta) heated = heated || b > 0;
  s += heated ? "  beta: " + mapping(x, x.beta) + "\n" : "  thermostat: none\n";
  bool drag = false;
  for (double g : x.drag) drag = drag || g > 0;
  if (drag) s += "  drag: {gamma: " + mapping(x, x.drag) + "}\n";
  s += "  gamma: " + number(x.kgamma) + "\n  kernel: {lambda: 0, C: " + number(x.C) + "}\n";
  s += "  initial: {temperature: " + number(x.T0) + "}\n  t_end: " + number(t_end) +
       "\n  observe_every: " + number(every) + "\n";
  if (steady_from > 0) s += "  steady_from: " + number(steady_from) + "\n";
  if (x.scheme != "nosplit")
    s += "  scheme: " + x.scheme + "\n  steps: " + std::to_string(std::lround(t_end / x.dt)) + "\n";
  return s;
}

std::string run(const TempDir& dir, const std::string& name, const std::string& text) {
  const std::string cfg = dir.write(name + ".yaml", text), out = dir.file(name + ".h5");
  const auto r = run_granboltz("run " + cfg + " -q -o " + out);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return out;
}

// The largest |mean - exact| / sigma over the rows and species of T_a(t), and of the steady
// ratio T_a/T_b (the exact one from the time average of the exact rows t_m > steady_from).
struct Deviation {
  double rows = 0.0, ratio = 0.0;
  int checks = 0;
};

Deviation deviation(const H5Reader& f, const Mixture& x, int ensembles, double steady_from,
                    const Perturb& p = {}) {
  const auto times = f.read_double("/time");
  const auto T = exact_temperatures(x, times, p);
  Deviation dev;
  std::vector<double> avg(x.mass.size(), 0.0);
  for (std::size_t a = 0; a < x.mass.size(); ++a) {
    const std::string g = "/species/" + x.names[a] + "/temperature";
    const auto mean = f.read_double(g + "/mean"), var = f.read_double(g + "/variance");
    int rows = 0;
    for (std::size_t m = 1; m < times.size(); ++m) {  // row 0: the initial state, T0 exactly in law
      const double sigma = std::sqrt(var[m] / ensembles);
      dev.rows = std::max(dev.rows, std::fabs(mean[m] - T[a][m]) / sigma);
      ++dev.checks;
      if (times[m] > steady_from) avg[a] += T[a][m], ++rows;
    }
    avg[a] /= rows;
  }
  if (steady_from > 0) {
    const std::string g = "/steady/temperature_ratio/" + x.names[0] + "_over_" + x.names[1];
    const double r = f.read_double(g + "/mean")[0], s = f.read_double(g + "/sigma")[0];
    dev.ratio = std::fabs(r - avg[0] / avg[1]) / s;
    ++dev.checks;
  }
  return dev;
}

// The exact comparison of one mixture, and the rejection of the perturbed systems.
void expect_exact(const Mixture& x, int seed, int ensembles, double t_end, double every,
                  double steady_from) {
  TempDir dir;
  H5Reader f(run(dir, "m", config_text(x, seed, ensembles, t_end, every, steady_from)));
  const Deviation dev = deviation(f, x, ensembles, steady_from);
  const double z = test::family_z(dev.checks);
  EXPECT_LT(dev.rows, z) << "T_a(t) rows, family of " << dev.checks;
  EXPECT_LT(dev.ratio, z) << "steady T_a/T_b";
  // The same data reject a 5 % error in the collision rate, and a factor 2 in the heating and in
  // the drag of the first species that has them.
  std::vector<Perturb> wrong{Perturb{1.05}};
  const std::size_t heated = x.beta[0] > 0 ? 0 : 1, dragged = x.drag[0] > 0 ? 0 : 1;
  if (x.beta[heated] > 0) {
    Perturb p;
    p.beta[heated] = 2.0;
    wrong.push_back(p);
  }
  if (x.drag[dragged] > 0) {
    Perturb p;
    p.drag[dragged] = 2.0;
    wrong.push_back(p);
  }
  for (const Perturb& p : wrong) {
    const Deviation w = deviation(f, x, ensembles, steady_from, p);
    EXPECT_GT(std::max(w.rows, w.ratio), z)
        << "a wrong system passes: rate x" << p.rate << ", beta x" << p.beta[0] << "," << p.beta[1]
        << ", drag x" << p.drag[0] << "," << p.drag[1];
  }
}

}  // namespace

// Species-dependent white noise: the light species heated five times more than the heavy one.
TEST(GasFlight, PerSpeciesHeatingFollowsTheExactTemperatureEquations) {
  Mixture x;
  x.C = 1.0 / x.area();
  x.beta = {1.0, 0.2};
  expect_exact(x, 11, 400, 5.0, 0.25, 2.0);
}

// Species-dependent drag with one noise strength (written as a mapping of equal values).
TEST(GasFlight, PerSpeciesDragFollowsTheExactTemperatureEquations) {
  Mixture x;
  x.C = 1.0 / x.area();
  x.beta = {0.5, 0.5};
  x.drag = {1.0, 0.1};
  expect_exact(x, 12, 400, 5.0, 0.25, 2.0);
}

// Both per species, in the plane: uniform directions and hard-disk impacts (chi = 4/3).
TEST(GasFlight, PerSpeciesHeatingAndDragInThePlane) {
  for (bool impact : {false, true}) {
    Mixture x;
    x.d = 2;
    x.impact = impact;
    x.C = 1.0 / x.area();
    x.beta = {0.2, 1.0};
    x.drag = {0.3, 0.8};
    expect_exact(x, impact ? 14 : 13, 400, 5.0, 0.25, 2.0);
  }
}

// The splitting schemes: collisions and flights in turn over the step (the flights over dt at
// once, kick_all_by). Their expected moments are again exact (the composition of the two exact
// linear maps), and with a coarse step (dt = 0.5, a collision time) they differ from the
// no-splitting solution by more than the statistics resolve.
TEST(GasFlight, SplittingSchemesFollowTheirExactSplitEquations) {
  for (const char* scheme : {"strang", "euler"}) {
    Mixture x;
    x.C = 1.0 / x.area();
    x.beta = {1.0, 0.2};
    x.drag = {0.8, 0.1};
    x.scheme = scheme;
    x.dt = 0.5;
    expect_exact(x, std::string(scheme) == "strang" ? 17 : 18, 400, 5.0, 0.5, 2.0);
    TempDir dir;
    H5Reader f(run(dir, "s", config_text(x, 19, 400, 5.0, 0.5, 2.0)));
    Mixture unsplit = x;
    unsplit.scheme = "nosplit";
    const Deviation w = deviation(f, unsplit, 400, 2.0);
    EXPECT_GT(std::max(w.rows, w.ratio), test::family_z(w.checks))
        << scheme << ": the split is resolved";
  }
}

// Drag alone (thermostat none): the mixture cools faster than by its collisions, each species at
// its own friction; and one species written with dsmc.species (the general engine) under drag
// and noise relaxes as dT/dt = -zeta T + 2 m beta - 2 gamma T with its finite-n terms.
TEST(GasFlight, DragAloneAndOneSpecies) {
  Mixture x;
  x.C = 1.0 / x.area();
  x.drag = {0.5, 0.05};
  x.alpha = 0.9;
  expect_exact(x, 15, 400, 4.0, 0.25, 0.0);
  Mixture one;
  one.C = 1.0 / one.area();
  one.names = {"g"};
  one.fraction = {1.0};
  one.mass = {2.0};
  one.diameter = {1.0};
  one.beta = {0.7};
  one.drag = {0.4};
  one.T0 = 0.2;
  TempDir dir;
  std::string text = config_text(one, 16, 400, 4.0, 0.25, 0.0);
  H5Reader f(run(dir, "one", text));
  const auto times = f.read_double("/time");
  const auto T = exact_temperatures(one, times);
  const auto mean = f.read_double("/species/g/temperature/mean");
  const auto var = f.read_double("/species/g/temperature/variance");
  const double z = test::family_z(static_cast<int>(times.size()) - 1);
  for (std::size_t m = 1; m < times.size(); ++m)
    EXPECT_LT(std::fabs(mean[m] - T[0][m]), z * std::sqrt(var[m] / 400)) << times[m];
}

// A mapping of equal values is the scalar key: dsmc.beta {a: b, b: b} draws the white-noise kicks
// of dsmc.beta = b, and drag {gamma: {a: g, b: g}} the flight of gamma = g, bit for bit.
TEST(GasFlight, EqualValuesPerSpeciesAreTheScalarKeyBitForBit) {
  const std::string base =
      "model: dsmc\nseed: 5\nensembles: 1\ndsmc:\n  particles: 300\n  species:\n"
      "    - {name: a, fraction: 0.5, mass: 1, diameter: 1}\n"
      "    - {name: b, fraction: 0.5, mass: 3, diameter: 2}\n"
      "  alpha: 0.7\n  kernel: {lambda: 1, C: 0.08}\n  t_end: 2\n  observe_every: 1\n";
  for (const auto& [scalar, map] : std::vector<std::pair<std::string, std::string>>{
           {"  beta: 0.6\n", "  beta: {a: 0.6, b: 0.6}\n"},
           {"  beta: 0.6\n  drag: {gamma: 0.3}\n",
            "  beta: 0.6\n  drag: {gamma: {a: 0.3, b: 0.3}}\n"}}) {
    const Config c1 = parse_config(base + scalar, "s.yaml", {});
    const Config c2 = parse_config(base + map, "m.yaml", {});
    GasEnsemble e1(c1.dsmc, 5, 0), e2(c2.dsmc, 5, 0);
    e1.advance_to(2.0);
    e2.advance_to(2.0);
    for (std::size_t i = 0; i < e1.particles().size(); ++i) {
      const Vec3 &u = e1.particles()[i].v, &w = e2.particles()[i].v;
      ASSERT_TRUE(u.x == w.x && u.y == w.y && u.z == w.z) << map << i;
    }
    EXPECT_EQ(e1.counts().collisions, e2.counts().collisions);
    EXPECT_EQ(e1.counts().kicks, e2.counts().kicks);
  }
}

// Rough particles: the flight moves the translational velocities only. With a smooth contact
// (roughness.beta = -1) no collision turns a spin either, so every spin keeps its initial value
// under drag and noise, while the velocities move.
TEST(GasFlight, RoughParticlesFlyWithTheirSpinsUntouched) {
  const std::string text =
      "model: dsmc\nseed: 2\nensembles: 1\ndsmc:\n  particles: 400\n  species:\n"
      "    - {name: a, fraction: 0.5, mass: 1, diameter: 1}\n"
      "    - {name: b, fraction: 0.5, mass: 2, diameter: 1}\n"
      "  roughness: {beta: -1, inertia: 0.4}\n"
      "  alpha: 0.8\n  beta: {a: 1, b: 0.1}\n  drag: {gamma: {a: 0.2, b: 2}}\n"
      "  kernel: {lambda: 1, C: 0.08}\n  t_end: 2\n  observe_every: 1\n";
  const Config c = parse_config(text, "r.yaml", {});
  GasEnsemble e(c.dsmc, 2, 0);
  const std::vector<Vec3> spins = e.spins();
  const Particles before = e.particles();
  e.advance_to(2.0);
  ASSERT_EQ(e.spins().size(), spins.size());
  for (std::size_t i = 0; i < spins.size(); ++i) {
    const Vec3 &u = e.spins()[i], &w = spins[i];
    ASSERT_TRUE(u.x == w.x && u.y == w.y && u.z == w.z) << i;
  }
  std::size_t moved = 0;
  for (std::size_t i = 0; i < before.size(); ++i) moved += before[i].v.x != e.particles()[i].v.x;
  EXPECT_EQ(moved, before.size());
}

namespace {
const std::string kDragMixture = R"(model: dsmc
seed: 9
ensembles: 5
dsmc:
  particles: 301
  species:
    - {name: light, fraction: 0.6, mass: 1, diameter: 1}
    - {name: heavy, fraction: 0.4, mass: 5, diameter: 1.4}
  roughness: {beta: 0.2, inertia: 0.4}
  alpha: 0.8
  beta: {light: 1, heavy: 0.3}
  drag: {gamma: {light: 0.5, heavy: 0.05}}
  kernel: {lambda: 1, C: 0.0795774715459477}
  initial: {temperature: 1.0}
  t_end: 4
  observe_every: 0.5
  steady_from: 1
)";
}  // namespace

// Threads, shards and a signal's checkpoint: the same outputs bit for bit, for the lazy flights
// (no splitting) and the flights over the step (Strang).
TEST(GasFlight, ThreadsShardsAndSignalsAreBitIdentical) {
  for (const std::string extra : {"", " --set dsmc.scheme=strang --set dsmc.steps=40"}) {
    TempDir dir;
    test::expect_threads_and_shards_identical(dir, dir.write("c.yaml", kDragMixture) + extra);
  }
  std::string longer = kDragMixture;
  longer.replace(longer.find("ensembles: 5"), 12, "ensembles: 4");
  longer.replace(longer.find("particles: 301"), 14, "particles: 100000");
  longer += "checkpoint: {every_seconds: 3600}\n";
  TempDir dir;
  test::expect_sigterm_resumes_identically(dir, dir.write("c.yaml", longer));
}

TEST(GasFlight, RestoredEnsembleContinuesIdentically) {
  for (const char* scheme : {"nosplit", "strang"}) {
    std::vector<std::string> sets{std::string("dsmc.scheme=") + scheme};
    if (std::string(scheme) == "strang") sets.push_back("dsmc.steps=40");
    const Config config = parse_config(kDragMixture, "c.yaml", sets);
    TempDir dir;
    GasEnsemble a(config.dsmc, 3, 1);
    a.advance_to(1.5);
    {
      H5Writer w(dir.file("state.h5"));
      a.save(w, "/e");
      w.commit();
    }
    H5Reader r(dir.file("state.h5"));
    GasEnsemble b(config.dsmc, r, "/e");
    a.advance_to(4);
    b.advance_to(4);
    for (std::size_t i = 0; i < a.particles().size(); ++i) {
      const Particle &p = a.particles()[i], &q = b.particles()[i];
      ASSERT_TRUE(p.v.x == q.v.x && p.v.y == q.v.y && p.v.z == q.v.z && p.t == q.t) << i;
      const Vec3 &u = a.spins()[i], &w = b.spins()[i];
      ASSERT_TRUE(u.x == w.x && u.y == w.y && u.z == w.z) << i;
    }
    EXPECT_EQ(a.counts().collisions, b.counts().collisions);
    EXPECT_EQ(a.counts().kicks, b.counts().kicks);
  }
}
