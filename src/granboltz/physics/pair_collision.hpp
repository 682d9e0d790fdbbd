#pragma once
// The collision of two particles of species a and b with masses and, optionally, rough surfaces
// (spheres in d = 3, disks in d = 2). In d = 2 velocities have z = 0 and an angular velocity is
// Vec3{0, 0, omega}; the cross products below then keep both in their planes, so one code serves
// both dimensions.
#include <cfloat>
#include <cmath>

#include "granboltz/core/hot.hpp"
#include "granboltz/core/vec3.hpp"

namespace granboltz {

inline Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

/// The terms of one pair of species (a, b), computed once per pair of species.
struct PairTerms {
  double mu_a = 0.5, mu_b = 0.5;  // m_a/(m_a+m_b), m_b/(m_a+m_b)
  double r_a = 0.5, r_b = 0.5;    // radii sigma/2
  double tangential = 0.0;  // t = (1+beta) k/(1+k), 1/k = m_ab (r_a^2/I_a + r_b^2/I_b); 0: smooth
  double spin_a = 0.0, spin_b = 0.0;  // m_ab r_a / I_a, m_ab r_b / I_b  (m_ab = m_a m_b/(m_a+m_b))
};

/// Builds them from masses, diameters, the tangential restitution beta in [-1,1] and the
/// reduced moments of inertia kappa_a = 4 I_a/(m_a sigma_a^2) (I = kappa m r^2). kappa <= 0 (of
/// either species): smooth. With I = kappa m r^2 the masses and radii cancel in part:
/// 1/k = mu_b/kappa_a + mu_a/kappa_b and m_ab r_a/I_a = mu_b/(kappa_a r_a); for equal spheres
/// k = kappa, t = (1+beta) kappa/(1+kappa) and spin = 1/(kappa sigma).
inline PairTerms pair_terms(double m_a, double m_b, double sigma_a, double sigma_b, double beta,
                            double kappa_a, double kappa_b) {
  PairTerms p;
  const double m = m_a + m_b;
  p.mu_a = m_a / m;
  p.mu_b = m_b / m;
  p.r_a = 0.5 * sigma_a;
  p.r_b = 0.5 * sigma_b;
  if (kappa_a > 0 && kappa_b > 0) {
    const double inv_k = p.mu_b / kappa_a + p.mu_a / kappa_b;
    p.tangential = (1.0 + beta) / (1.0 + inv_k);  // (1+beta) k/(1+k)
    p.spin_a = p.mu_b / (kappa_a * p.r_a);
    p.spin_b = p.mu_a / (kappa_b * p.r_b);
  }
  return p;
}

/// The impact normal from GRW05's direction e: n = (u^ - e)/|u^ - e|, u = v_a - v_b, so u.n >= 0;
/// returns false (pair left untouched by the caller) when |u| = 0 or |u^ - e| = 0, and also for
/// the nearly grazing |u^ - e|^2 <= DBL_EPSILON (|u^ - e| < 1.5e-8): the rounding of u^ turns n by
/// about DBL_EPSILON/|u^ - e|, which moves u.n (u nearly normal to n) by |u| times that, more than
/// the exact impulse (1+eps)/4 |u| |u^ - e| that declining drops, at most 1e-8 |u|. u.n < 0 from
/// rounding is declined as well.
GRANBOLTZ_HOT bool impact_normal(Vec3 u, Vec3 e, Vec3& n) {
  const double u2 = norm2(u);
  if (!(u2 > 0)) return false;
  const Vec3 d = (1.0 / std::sqrt(u2)) * u - e;
  const double d2 = norm2(d);
  if (!(d2 > DBL_EPSILON)) return false;
  const Vec3 c = (1.0 / std::sqrt(d2)) * d;
  if (dot(u, c) < 0) return false;
  n = c;
  return true;
}

/// Smooth particles with masses: J = (1+eps)(u.n) n; v_a -= mu_b J, v_b += mu_a J.
/// Returns g_n = u.n before the collision.
GRANBOLTZ_HOT double collide_smooth(Vec3& va, Vec3& vb, Vec3 n, double eps, const PairTerms& p) {
  const double gn = dot(va - vb, n);
  const Vec3 J = ((1.0 + eps) * gn) * n;
  va = va - p.mu_b * J;
  vb += p.mu_a * J;
  return gn;
}

/// Rough: contact velocity g = u + (r_a w_a + r_b w_b) x n (n points from a to b);
/// g_t = g - (g.n) n; J = (1+eps)(u.n) n + t g_t; v_a -= mu_b J; v_b += mu_a J;
/// w_a -= spin_a (n x (t g_t)); w_b -= spin_b (n x (t g_t)).
/// The impulse on b is m_ab J, applied at the contact point, so momentum and the angular momentum
/// about that point are conserved, g_n' = -eps g_n and g_t' = -beta g_t. The normal part uses
/// collide_smooth's expressions and the tangential part is skipped when t == 0 (beta = -1 or
/// smooth), so that case equals collide_smooth bit for bit with the spins untouched.
/// Returns g_n = u.n before the collision.
GRANBOLTZ_HOT double collide_rough(Vec3& va, Vec3& wa, Vec3& vb, Vec3& wb, Vec3 n, double eps,
                                   const PairTerms& p) {
  const Vec3 u = va - vb;
  const double gn = dot(u, n);
  Vec3 J = ((1.0 + eps) * gn) * n;
  if (p.tangential != 0.0) {
    const Vec3 g = u + cross(p.r_a * wa + p.r_b * wb, n);
    const Vec3 Jt = p.tangential * (g - dot(g, n) * n);
    J += Jt;
    const Vec3 nJ = cross(n, Jt);
    wa = wa - p.spin_a * nJ;
    wb = wb - p.spin_b * nJ;
  }
  va = va - p.mu_b * J;
  vb += p.mu_a * J;
  return gn;
}

/// Kinetic energy of the pair, (m_a |v_a|^2 + I_a |w_a|^2 + m_b |v_b|^2 + I_b |w_b|^2)/2.
inline double pair_energy(double m_a, double I_a, Vec3 va, Vec3 wa, double m_b, double I_b, Vec3 vb,
                          Vec3 wb) {
  return 0.5 * (m_a * norm2(va) + I_a * norm2(wa) + m_b * norm2(vb) + I_b * norm2(wb));
}

}  // namespace granboltz
