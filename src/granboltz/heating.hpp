#pragma once
// The white-noise heating of GRW05 eq. (23): Brownian motion of a velocity over a time s.
#include <cmath>

#include "granboltz/samplers.hpp"
#include "granboltz/vec3.hpp"

namespace granboltz {

/// v + sqrt(2 beta s) xi with xi standard normal in R^3 (GRW05 eq. 23, RW05 eq. 9).
template <class E>
inline Vec3 white_noise_kick(Vec3 v, double beta, double s, E& eng) {
  return v + std::sqrt(2.0 * beta * s) * normal3(eng);
}

}  // namespace granboltz
