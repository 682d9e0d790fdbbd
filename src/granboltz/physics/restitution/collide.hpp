#pragma once
// A collision with a restitution law that depends on the normal relative speed (any d).
#include <algorithm>
#include <cmath>
#include <variant>

#include "granboltz/core/hot.hpp"
#include "granboltz/core/vec3.hpp"
#include "granboltz/physics/collision.hpp"
#include "granboltz/physics/restitution/laws.hpp"

namespace granboltz {

/// The normal relative speed squared, g_n^2 = (u.n)^2 = |u|^2 (1 - u.e/|u|)/2, for the impact
/// normal n = (u/|u| - e)/|u/|u| - e| that GRW05's direction e stands for, in any dimension (in
/// d = 3 with e uniform its density is proportional to u.n, that of hard-sphere impacts;
/// physics/geometry.hpp).
GRANBOLTZ_HOT double normal_speed2(Vec3 v, Vec3 w, Vec3 e) {
  const Vec3 u = v - w;
  const double u2 = norm2(u);
  return std::max(0.0, 0.5 * (u2 - std::sqrt(u2) * dot(u, e)));
}

/// The impact-normal collision v' = v - (1+eps)/2 (u.n) n, w' = w + (1+eps)/2 (u.n) n with eps =
/// law(g_n). Since (u.n) n = (u - |u| e)/2 this is collide(v, w, e, eps) exactly: GRW05's map with
/// alpha = eps, without dividing by |u/|u| - e| (0 for grazing impacts); written out here with
/// collide()'s expressions (the same bits) so that |u| is taken once. s2 is the square of the
/// factor from the velocities given to the true ones (Gaussian thermostat's lazy scale; else 1):
/// eps is taken at the true g_n, and the map, linear in (v, w) for a fixed eps, acts on the given
/// ones. Returns eps.
template <class Law>
GRANBOLTZ_HOT double collide_law(Vec3& v, Vec3& w, Vec3 e, const Law& law, double s2) {
  const Vec3 u = v - w;
  const double u2 = norm2(u), nu = std::sqrt(u2);
  double g2 = std::max(0.0, 0.5 * (u2 - nu * dot(u, e)));  // normal_speed2(v, w, e)
  if constexpr (!Law::kScaleFree) g2 *= s2;
  const double eps = law.eps_of_g2(g2);
  const Vec3 centre = 0.5 * (v + w);
  const Vec3 d = (0.25 * (1.0 - eps)) * u + (0.25 * (1.0 + eps) * nu) * e;
  v = centre + d;
  w = centre - d;
  return eps;
}

/// The same for a law chosen at run time (the engines call it only for non-constant laws).
GRANBOLTZ_HOT double collide_law(Vec3& v, Vec3& w, Vec3 e, const RestitutionLaw& law, double s2) {
  return std::visit([&](const auto& l) { return collide_law(v, w, e, l, s2); }, law);
}

}  // namespace granboltz
