#pragma once
// Free flight "drag": dv = -gamma_d v dt, with the white noise of strength beta an
// Ornstein-Uhlenbeck process (the stochastic thermostat with friction), key dsmc.drag.gamma.
// Exact: v(s) = e^{-gamma s} v + sqrt(beta (1 - e^{-2 gamma s}) / gamma) xi. Without collisions
// the temperature relaxes to beta / gamma_d at the rate 2 gamma_d.
#include "granboltz/physics/flight/propagator.hpp"

namespace granboltz::flight {

struct Drag {
  static constexpr const char* kName = "drag";
  static constexpr const char* kKey = "gamma";
  static constexpr const char* kMeaning = "friction per unit time gamma_d: dv = -gamma_d v dt";
  static constexpr bool kPerSpecies = true;  // a mapping of species names is allowed
  static constexpr bool kNegative = false;   // the parameter must be >= 0
  static void add(LinearFlight& f, double gamma) { f.gamma += gamma; }
};

}  // namespace granboltz::flight
