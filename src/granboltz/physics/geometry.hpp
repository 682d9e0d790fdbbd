#pragma once
// The collision geometry (dsmc.dimension, dsmc.geometry): the law of the direction e that
// GRW05's map (collision.hpp) is given, v' = (v+w)/2 + (1-eps)/4 u + (1+eps)/4 |u| e.
//
// That map is the impact map v' = v - (1+eps)/2 (u.n) n with the normal n = (u^ - e)/|u^ - e|,
// since (u.n) n = (u - |u| e)/2 in any dimension, so a geometry only has to say how e is drawn:
// - Sphere3: e uniform on S^2 (GRW05 eq. 4). Then n has density proportional to (u^.n)+ on the
//   hemisphere, which is the hard-sphere impact law: in d = 3 `uniform` and `impact` are one law.
// - CircleUniform: e uniform on S^1, a model of its own. Its n has a uniform impact angle, not the
//   hard-disk law (deflections are spread differently).
// - CircleImpact: hard disks. The impact angle theta between u^ and n has density cos(theta)/2 on
//   (-pi/2, pi/2), i.e. sin(theta) uniform on (-1, 1) (the rate of a disk pair is proportional to
//   u.n); then e = u^ - 2 (u^.n) n = -(cos 2theta u^ + sin 2theta u^_perp).
// Velocities of d = 2 runs have z = 0, and every e below keeps it 0 exactly.
#include <cstdint>

#include "granboltz/core/hot.hpp"
#include "granboltz/core/vec3.hpp"
#include "granboltz/random/samplers.hpp"

namespace granboltz {

struct Sphere3 {
  static constexpr int kDim = 3;
  template <class E>
  GRANBOLTZ_HOT static Vec3 direction(Vec3, E& eng) {
    return unit_vector(eng);
  }
};

/// A uniform direction on S^1 without trigonometry (von Neumann 1951): (a, b) uniform in the unit
/// disk gives the angle 2 atan2(b, a), uniform, as ((a^2 - b^2), 2ab)/(a^2 + b^2). One 64-bit
/// draw per trial (32 bits per coordinate), pi/4 of them accepted.
template <class E>
GRANBOLTZ_HOT Vec3 unit_circle(E& eng) {
  for (;;) {
    double a, b;
    square_point(eng(), a, b);
    const double s = a * a + b * b;
    if (s < 1.0) {
      const double inv = 1.0 / s;
      return {(a * a - b * b) * inv, 2.0 * a * b * inv, 0.0};
    }
  }
}

struct CircleUniform {
  static constexpr int kDim = 2;
  template <class E>
  GRANBOLTZ_HOT static Vec3 direction(Vec3, E& eng) {
    return unit_circle(eng);
  }
};

/// The hard-disk direction for the relative velocity u (in the plane): one uniform draw.
template <class E>
GRANBOLTZ_HOT Vec3 disk_impact_direction(Vec3 u, E& eng) {
  const double s = 2.0 * uniform01(eng) - 1.0;  // sin(theta)
  const double u2 = u.x * u.x + u.y * u.y;
  if (!(u2 > 0.0)) return {1.0, 0.0, 0.0};  // u = 0: the map does not move the pair
  const double inv = 1.0 / std::sqrt(u2);
  const double cx = u.x * inv, cy = u.y * inv;           // u^
  const double cos2 = 1.0 - 2.0 * s * s;                 // cos 2theta
  const double sin2 = 2.0 * s * std::sqrt(1.0 - s * s);  // sin 2theta
  // u^_perp = (-cy, cx)
  return {-(cos2 * cx - sin2 * cy), -(cos2 * cy + sin2 * cx), 0.0};
}

struct CircleImpact {
  static constexpr int kDim = 2;
  template <class E>
  GRANBOLTZ_HOT static Vec3 direction(Vec3 u, E& eng) {
    return disk_impact_direction(u, eng);
  }
};

/// |S^{d-1}|: the kernel C |u|^lambda integrated over the directions (4 pi, 2 pi).
constexpr double sphere_area(int d) { return d == 2 ? 2.0 * M_PI : 4.0 * M_PI; }

}  // namespace granboltz
