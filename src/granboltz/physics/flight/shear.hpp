#pragma once
// Free flight "shear": uniform shear flow u = a y e_x seen in the Lees-Edwards frame, where the
// peculiar velocity drifts as dv_x/dt = -a v_y (the homogeneous form of the USF Boltzmann
// equation, d_t f - a v_y d f/d v_x = J[f]), key dsmc.shear.rate. Exact: v_x(s) = v_x - a s v_y.
// The drift heats the gas at -2 a P_xy / (d rho) per unit time; a speed grows by at most the norm
// of I - a s e_x e_y^T, ((a s) + sqrt((a s)^2 + 4)) / 2, which the engines' majorant allows for.
#include <cmath>

#include "granboltz/physics/flight/propagator.hpp"

namespace granboltz::flight {

struct Shear {
  static constexpr const char* kName = "shear";
  static constexpr const char* kKey = "rate";
  static constexpr const char* kMeaning = "shear rate a of the flow u = a y e_x";
  static constexpr bool kPerSpecies = false;  // one flow for every species
  static constexpr bool kNegative = true;     // a < 0 is the flow reversed
  static void add(LinearFlight& f, double rate) { f.shear += rate; }
  /// The no-splitting loop's majorant window, in units of 1/|a|: over it a speed grows by at
  /// most growth(kWindow) = 1.25, so the acceptance costs at most 1/1.25 of the events, and the
  /// O(n) sync at each window's end stays a small part of the collisions in it.
  static constexpr double kWindow = 0.45;
  /// The operator norm of exp(-A s) for A = a e_x e_y^T: the most a speed can grow over s.
  static double growth(double as) { return 0.5 * (std::abs(as) + std::sqrt(as * as + 4.0)); }
};

}  // namespace granboltz::flight
