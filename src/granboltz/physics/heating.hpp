#pragma once
// The white-noise heating of GRW05 eq. (23): Brownian motion of a velocity over a time s.
#include <cmath>

#include "granboltz/core/hot.hpp"
#include "granboltz/core/vec3.hpp"
#include "granboltz/random/samplers.hpp"

namespace granboltz {

/// v + sqrt(2 beta s) xi with xi standard normal in R^3 (GRW05 eq. 23, RW05 eq. 9).
template <class E>
inline Vec3 white_noise_kick(Vec3 v, double beta, double s, E& eng) {
  return v + std::sqrt(2.0 * beta * s) * normal3(eng);
}

/// The same in the plane (d = 2): z stays 0.
template <class E>
inline Vec3 white_noise_kick_2d(Vec3 v, double beta, double s, E& eng) {
  const double k = std::sqrt(2.0 * beta * s);
  const double a = normal(eng);
  const double b = normal(eng);
  return {v.x + k * a, v.y + k * b, v.z};
}

/// Kicks two velocities, over the times sa and sb, with 2d normals from (usually) d draws.
template <int D = 3, class E>
GRANBOLTZ_HOT void white_noise_kick2(Vec3& a, double sa, Vec3& b, double sb, double beta, E& eng) {
  if constexpr (D == 2) {
    double n[4];
    normal_pair(eng, n[0], n[1]);
    normal_pair(eng, n[2], n[3]);
    const double ka = std::sqrt(2.0 * beta * sa), kb = std::sqrt(2.0 * beta * sb);
    a.x += ka * n[0], a.y += ka * n[1];
    b.x += kb * n[2], b.y += kb * n[3];
    return;
  }
  double n[6];
  normal_pair(eng, n[0], n[1]);
  normal_pair(eng, n[2], n[3]);
  normal_pair(eng, n[4], n[5]);
  const double ka = std::sqrt(2.0 * beta * sa), kb = std::sqrt(2.0 * beta * sb);
  a += Vec3{ka * n[0], ka * n[1], ka * n[2]};
  b += Vec3{kb * n[3], kb * n[4], kb * n[5]};
}

}  // namespace granboltz
