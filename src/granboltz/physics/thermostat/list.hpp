#pragma once
// The registry of thermostats: config reads their names from it, and the engines dispatch a
// run's thermostat to its compile-time struct through it.
#include <string>

#include "granboltz/physics/thermostat/gaussian.hpp"
#include "granboltz/physics/thermostat/kind.hpp"
#include "granboltz/physics/thermostat/none.hpp"
#include "granboltz/physics/thermostat/white_noise.hpp"

namespace granboltz {

template <class... Ts>
struct ThermostatTypes {
  /// Calls f(T{}) for every thermostat, in order.
  template <class F>
  static void each(F&& f) {
    (f(Ts{}), ...);
  }
  /// Calls f(T{}) for the thermostat whose kId is id.
  template <class F>
  static void with(Thermostat id, F&& f) {
    ((Ts::kId == id ? (f(Ts{}), 0) : 0), ...);
  }
};

using ThermostatList = ThermostatTypes<WhiteNoiseThermostat, GaussianThermostat, NoThermostat>;

inline const char* thermostat_name(Thermostat t) {
  const char* name = "?";
  ThermostatList::each([&](auto th) {
    if (decltype(th)::kId == t) name = decltype(th)::kName;
  });
  return name;
}

}  // namespace granboltz
