#pragma once
// Free flight "white_noise": dv = sqrt(2 beta) dW (GRW05 eq. 1, 23), key dsmc.beta. The
// one-species engines keep their tuned kicks (physics/heating.hpp), which draw the same law.
#include "granboltz/physics/flight/propagator.hpp"

namespace granboltz::flight {

struct WhiteNoise {
  static constexpr const char* kName = "white_noise";
  static constexpr const char* kKey = "beta";
  static constexpr const char* kMeaning = "noise strength beta: <|dv|^2> = 2 d beta dt";
  /// Its part of the linear flight: A = 0, B = sqrt(2 beta) I.
  static void add(LinearFlight& f, double beta) { f.beta += beta; }
};

}  // namespace granboltz::flight
