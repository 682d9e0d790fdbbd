#pragma once
// The registry of free flights. A flight is one header in this folder (a struct with kName,
// the config key kKey of its parameter, kMeaning, and add(), which puts its part into the
// LinearFlight whose exact propagator every engine uses) plus one entry here. Its config is
// dsmc.<kName>: {<kKey>: value}, a number or a mapping of species names to numbers; white noise
// keeps the papers' key dsmc.beta.
#include "granboltz/physics/flight/drag.hpp"
#include "granboltz/physics/flight/propagator.hpp"
#include "granboltz/physics/flight/shear.hpp"
#include "granboltz/physics/flight/white_noise.hpp"

namespace granboltz::flight {

template <class... Fs>
struct FlightTypes {
  static constexpr int kCount = sizeof...(Fs);
  /// Calls f(F{}, k) for every flight F, k its index.
  template <class F>
  static void each(F&& f) {
    int k = 0;
    (f(Fs{}, k++), ...);
  }
};

/// The flights read from dsmc.<name> sections (white noise, dsmc.beta, is read with the
/// thermostat).
using SectionFlights = FlightTypes<Drag, Shear>;

}  // namespace granboltz::flight
