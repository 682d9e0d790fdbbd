#pragma once
// The Gaussian thermostat: every peculiar velocity is rescaled, at all times, so that the
// temperature stays T0; in scaled variables this is the homogeneous cooling state (HCS).
//
// It acts lazily: the engine stores velocities w whose true values are v = V + s (w - V), with
// one factor s for all particles. A collision map is linear in (v, w) for a fixed eps, so it
// commutes with the scale; only the energy it removes changes s: s^2 = target / energy, energy
// = sum |w - V|^2 kept current collision by collision, target = d n T0. A law whose eps depends
// on the size of g_n takes it at the true speed (the stored one times s). The engine folds s into
// the stored velocities now and then (and before every observation), recomputing both sums
// exactly. This struct is that state, its arithmetic and the fold, which every engine calls.
#include <cmath>
#include <cstddef>
#include <span>

#include "granboltz/core/hot.hpp"
#include "granboltz/core/vec3.hpp"
#include "granboltz/physics/thermostat/kind.hpp"

namespace granboltz {

struct GaussianThermostat {
  static constexpr Thermostat kId = Thermostat::kGaussian;
  static constexpr const char* kName = "gaussian";
  static constexpr bool kKicks = false;
  static constexpr bool kLazyScale = true;
  double energy = 0.0;  ///< sum |w_i - V|^2 of the stored velocities
  double target = 0.0;  ///< sum |v_i - V|^2 of the true ones at the last fold (d n T0)
  double s2 = 1.0;      ///< s^2 = target / energy

  void set(double e, double t) {
    energy = e;
    target = t;
    s2 = target / energy;
  }
  /// A collision changed sum |w - V|^2 by delta: the scale grows to keep the true energy.
  GRANBOLTZ_HOT void after_collision(double delta) {
    energy += delta;
    s2 = target / energy;
  }
  /// The energy d G T0 of G particles' worth of weight at temperature T0 in d dimensions.
  static double target_of(int d, double G, double T0) { return static_cast<double>(d) * G * T0; }

  struct Folded {
    double factor;  ///< f
    double energy;  ///< sum g |v - V|^2 (+ I |W|^2) of the folded velocities
  };

  /// Folds the scale into the stored velocities: v_i = V + f (w_i - M), M = sum g w / G the
  /// weighted mean of the stored velocities (G = sum g) and f^2 = target(G) / K, K = sum g |w -
  /// M|^2 (+ I |W|^2 with spins, which scale by f too). Taking f from the exact sum, not from s,
  /// removes the drift of the running energy; centring on M, not on V, keeps the round-off momentum
  /// of the stored velocities (and an SWPM roulette's momentum noise) from being amplified by s at
  /// every fold. `each(fn)` calls fn(i, g_i, I_i) for every particle in one fixed order: the
  /// weight is 1, a species' mass or an SWPM weight, I the moment of inertia (read only with
  /// spins). The same sums in the same order in every engine: a fold's bits depend on them.
  template <class P, class Target, class Each>
  static Folded fold(std::span<P> p, std::span<Vec3> spins, Vec3 V, Target target, Each each) {
    Vec3 sum;
    double G = 0.0;
    each([&](std::size_t i, double g, double) {
      sum += g * p[i].v;
      G += g;
    });
    const Vec3 M = (1.0 / G) * sum;
    double k = 0.0;
    each([&](std::size_t i, double g, double I) {
      k += g * norm2(p[i].v - M);
      if (!spins.empty()) k += I * norm2(spins[i]);
    });
    const double f = std::sqrt(target(G) / k);
    for (auto& q : p) q.v = V + f * (q.v - M);
    for (auto& w : spins) w = f * w;
    double e = 0.0;
    each([&](std::size_t i, double g, double I) {
      e += spins.empty() ? g * norm2(p[i].v - V) : g * norm2(p[i].v - V) + I * norm2(spins[i]);
    });
    return {f, e};
  }
};

}  // namespace granboltz
