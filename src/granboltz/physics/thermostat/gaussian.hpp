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
// exactly. This struct is that state and its arithmetic; the folds live in the engines.
#include <cmath>

#include "granboltz/core/hot.hpp"
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
  /// The factor that brings peculiar velocities with sum of squares k to temperature T0 in d
  /// dimensions for n particles: sqrt(d n T0 / k).
  static double fold_factor(int d, double n, double T0, double k) {
    return std::sqrt(static_cast<double>(d) * n * T0 / k);
  }
};

}  // namespace granboltz
