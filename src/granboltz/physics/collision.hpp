#pragma once
// The inelastic collision map of GRW05 eq. (4) / RW05 eq. (4).
#include "granboltz/core/hot.hpp"
#include "granboltz/core/vec3.hpp"

namespace granboltz {

/// Replaces (v, w) by the post-collisional velocities for restitution alpha and direction e:
///   v' = (v+w)/2 + (1-alpha)/4 u + (1+alpha)/4 |u| e,
///   w' = (v+w)/2 - (1-alpha)/4 u - (1+alpha)/4 |u| e,   u = v - w.
/// Momentum v + w is conserved to round-off; see energy_change() for the energy.
GRANBOLTZ_HOT void collide(Vec3& v, Vec3& w, Vec3 e, double alpha) {
  const Vec3 u = v - w;
  const Vec3 centre = 0.5 * (v + w);
  const Vec3 d = (0.25 * (1.0 - alpha)) * u + (0.25 * (1.0 + alpha) * norm(u)) * e;
  v = centre + d;
  w = centre - d;
}

/// The exact change of |v|^2 + |w|^2 in collide() (GRW05 §2):
///   -(1 - alpha^2)/4 (1 - mu) |u|^2,  mu = (u, e)/|u|.
inline double energy_change(Vec3 v, Vec3 w, Vec3 e, double alpha) {
  const Vec3 u = v - w;
  const double nu = norm(u);
  const double mu = nu > 0 ? dot(u, e) / nu : 0.0;
  return -0.25 * (1.0 - alpha * alpha) * (1.0 - mu) * nu * nu;
}

}  // namespace granboltz
