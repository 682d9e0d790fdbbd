#pragma once
// No energy input: free cooling (Haff's law for hard spheres). White noise with beta = 0 runs
// this loop too, bit for bit.
#include "granboltz/physics/thermostat/kind.hpp"

namespace granboltz {

struct NoThermostat {
  static constexpr Thermostat kId = Thermostat::kNone;
  static constexpr const char* kName = "none";
  static constexpr bool kKicks = false;      // no kicks between the events
  static constexpr bool kLazyScale = false;  // the stored velocities are the true ones
};

}  // namespace granboltz
