#include "granboltz/dsmc/observables.hpp"

#include <cmath>
#include <stdexcept>

namespace granboltz {

namespace {
using V2 = double __attribute__((vector_size(16)));  // two doubles: one SSE2 register

/// The sums over particles of the central products, c = v - V: c_a c_b, c_a |c|^2, |c|^4 and
/// |c|^{2p}, p = 1..P.
struct CentralSums {
  V2 xx_yy = {0, 0}, zz_xy = {0, 0}, xz_yz = {0, 0};  // the second moments c_a c_b
  V2 qx_qy = {0, 0}, qz_c4 = {0, 0};                  // c_a |c|^2 and |c|^4
  double c2p[kMaxMoments] = {};                       // |c|^{2p}
};

/// Two sums per SSE2 instruction: each lane is one accumulator, which adds its terms in particle
/// order exactly as a scalar loop would, so the results are bit-identical. The number of speed
/// moments is a template parameter so that their sums stay in registers (a runtime count kept
/// them in memory, a store-to-load chain per term; with both changes measure() executes 36 %
/// fewer instructions).
template <int P = 0>
CentralSums central_sums(std::span<const Particle> particles, Vec3 V, int moment_count) {
  if constexpr (P < kMaxMoments)
    if (moment_count != P) return central_sums<P + 1>(particles, V, moment_count);
  V2 xx_yy = {0, 0}, zz_xy = {0, 0}, xz_yz = {0, 0}, qx_qy = {0, 0}, qz_c4 = {0, 0};
  double c2p[P > 0 ? P : 1] = {};
  const V2 Vxy = {V.x, V.y};
  for (const auto& q : particles) {
    const V2 cxy = V2{q.v.x, q.v.y} - Vxy;
    const double cz = q.v.z - V.z;
    const V2 sq = cxy * cxy;
    const double z2 = cz * cz;
    const double c2 = sq[0] + sq[1] + z2;  // norm2(c)
    xx_yy += sq;
    zz_xy += V2{z2, cxy[0] * cxy[1]};
    xz_yz += cxy * cz;
    qx_qy += cxy * c2;
    qz_c4 += V2{cz, c2} * c2;
    double power = 1.0;
#pragma GCC unroll 16
    for (int k = 0; k < P; ++k) {
      power *= c2;
      c2p[k] += power;
    }
  }
  CentralSums s{xx_yy, zz_xy, xz_yz, qx_qy, qz_c4, {}};
  for (int k = 0; k < P; ++k) s.c2p[k] = c2p[k];
  return s;
}
}  // namespace

double crit(double temperature, const double* pressure, const double* heat_flux,
            double fourth_moment, int dimension) {
  const double T = temperature;
  if (dimension == 2) {
    const double p = (pressure[0] + pressure[4]) / 2.0;
    const double d0 = pressure[0] - p, d1 = pressure[4] - p;
    const double frob = d0 * d0 + d1 * d1 + 2.0 * pressure[1] * pressure[1];
    const double q2 = heat_flux[0] * heat_flux[0] + heat_flux[1] * heat_flux[1];
    return std::sqrt(0.5 * frob + 2.0 / (4.0 * T) * q2 +
                     fourth_moment * fourth_moment / (64.0 * T * T)) /
           T;
  }
  const double p = (pressure[0] + pressure[4] + pressure[8]) / 3.0;
  double frob = 0.0;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      const double d = pressure[3 * a + b] - (a == b ? p : 0.0);
      frob += d * d;
    }
  const double q2 =
      heat_flux[0] * heat_flux[0] + heat_flux[1] * heat_flux[1] + heat_flux[2] * heat_flux[2];
  return std::sqrt(0.5 * frob + 2.0 / (5.0 * T) * q2 +
                   fourth_moment * fourth_moment / (120.0 * T * T)) /
         T;
}

std::string moment_name(int p) { return "moment_" + std::to_string(2 * p); }

Observation measure(std::span<const Particle> particles, std::span<double> moments, int dimension) {
  const double inv_n = 1.0 / static_cast<double>(particles.size());
  // The mean, two sums per SSE2 instruction (see central_sums).
  V2 mxy = {0, 0};
  double mz = 0.0;
  for (const auto& q : particles) {
    mxy += V2{q.v.x, q.v.y};
    mz += q.v.z;
  }
  const Vec3 V = inv_n * Vec3{mxy[0], mxy[1], mz};
  return measure_about(particles, V, moments, dimension);
}

Observation measure_about(std::span<const Particle> particles, Vec3 V, std::span<double> moments,
                          int dimension) {
  if (moments.size() > static_cast<std::size_t>(kMaxMoments))
    throw std::logic_error("measure: more than kMaxMoments speed moments");
  const std::size_t moment_count = moments.size();
  const double inv_n = 1.0 / static_cast<double>(particles.size());
  const CentralSums sums = central_sums(particles, V, static_cast<int>(moment_count));
  const double* c2p = sums.c2p;
  const double cc[6] = {sums.xx_yy[0], sums.xx_yy[1], sums.zz_xy[0],
                        sums.zz_xy[1], sums.xz_yz[0], sums.xz_yz[1]};
  const double flux[3] = {sums.qx_qy[0], sums.qx_qy[1], sums.qz_c4[0]};
  const double c4 = sums.qz_c4[1];
  for (std::size_t k = 0; k < moment_count; ++k) moments[k] = c2p[k] * inv_n;
  Observation o{};
  o[0] = 1.0;
  o[1] = V.x;
  o[2] = V.y;
  o[3] = V.z;
  double* P = &o[5];
  P[0] = cc[0] * inv_n;
  P[4] = cc[1] * inv_n;
  P[8] = cc[2] * inv_n;
  P[1] = P[3] = cc[3] * inv_n;
  P[2] = P[6] = cc[4] * inv_n;
  P[5] = P[7] = cc[5] * inv_n;
  // d = 2: P[8] = 0 exactly (v_z = 0), so the traces are the same sums.
  const double d = static_cast<double>(dimension);
  const double T = (P[0] + P[4] + P[8]) / d;
  o[4] = T;
  for (int a = 0; a < 3; ++a) o[14 + a] = 0.5 * flux[a] * inv_n;
  o[17] = c4 * inv_n - d * (d + 2.0) * T * T;
  o[18] = crit(T, P, &o[14], o[17], dimension);
  o[19] = T + norm2(V) / d;
  return o;
}

void radial_histogram(std::span<const Particle> particles, const HistogramSpec& spec, Vec3 V,
                      std::uint64_t* counts) {
  const std::uint64_t K = spec.shells;
  const double scale = static_cast<double>(K) / spec.radius;
  auto add = [&](double r) {
    const double k = std::floor(r * scale);
    ++counts[k < static_cast<double>(K) ? static_cast<std::uint64_t>(k) : K];
  };
  if (spec.bulk)
    for (const auto& q : particles) add(norm(q.v - V));
  else
    for (const auto& q : particles) add(norm(q.v));
}

std::uint64_t component_bin(double x, const HistogramSpec& spec) {
  const std::uint64_t K = spec.shells;
  // Written so that a NaN and |x| >= R fall through to the overflow bin.
  if (!(std::fabs(x) < spec.radius)) return K;
  const double k = std::floor((x + spec.radius) * (static_cast<double>(K) / (2.0 * spec.radius)));
  return k < static_cast<double>(K) ? static_cast<std::uint64_t>(k) : K - 1;
}

void component_histogram(std::span<const Particle> particles, const HistogramSpec& spec, Vec3 V,
                         std::uint64_t* counts) {
  for (const auto& q : particles) ++counts[component_bin(q.v.x - V.x, spec)];
}

}  // namespace granboltz
