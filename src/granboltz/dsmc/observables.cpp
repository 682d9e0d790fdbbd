#include "granboltz/dsmc/observables.hpp"

#include <cmath>
#include <stdexcept>

namespace granboltz {

double crit(double temperature, const double* pressure, const double* heat_flux,
            double fourth_moment) {
  const double p = (pressure[0] + pressure[4] + pressure[8]) / 3.0;
  double frob = 0.0;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      const double d = pressure[3 * a + b] - (a == b ? p : 0.0);
      frob += d * d;
    }
  const double q2 = heat_flux[0] * heat_flux[0] + heat_flux[1] * heat_flux[1] +
                    heat_flux[2] * heat_flux[2];
  const double T = temperature;
  return std::sqrt(0.5 * frob + 2.0 / (5.0 * T) * q2 +
                   fourth_moment * fourth_moment / (120.0 * T * T)) / T;
}

std::string moment_name(int p) { return "moment_" + std::to_string(2 * p); }

Observation measure(std::span<const Particle> particles, std::span<double> moments) {
  if (moments.size() > static_cast<std::size_t>(kMaxMoments))
    throw std::logic_error("measure: more than kMaxMoments speed moments");
  const std::size_t moment_count = moments.size();
  const double inv_n = 1.0 / static_cast<double>(particles.size());
  Vec3 m;
  for (const auto& q : particles) m += q.v;
  const Vec3 V = inv_n * m;

  double cc[6] = {0, 0, 0, 0, 0, 0};  // xx, yy, zz, xy, xz, yz
  double flux[3] = {0, 0, 0};
  double c4 = 0.0;
  double c2p[kMaxMoments] = {};  // sum |c|^{2p}, p = 1..moment_count
  for (const auto& q : particles) {
    const Vec3 c = q.v - V;
    const double c2 = norm2(c);
    cc[0] += c.x * c.x;
    cc[1] += c.y * c.y;
    cc[2] += c.z * c.z;
    cc[3] += c.x * c.y;
    cc[4] += c.x * c.z;
    cc[5] += c.y * c.z;
    flux[0] += c.x * c2;
    flux[1] += c.y * c2;
    flux[2] += c.z * c2;
    c4 += c2 * c2;
    double power = 1.0;
    for (std::size_t k = 0; k < moment_count; ++k) {
      power *= c2;
      c2p[k] += power;
    }
  }
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
  const double T = (P[0] + P[4] + P[8]) / 3.0;
  o[4] = T;
  for (int a = 0; a < 3; ++a) o[14 + a] = 0.5 * flux[a] * inv_n;
  o[17] = c4 * inv_n - 15.0 * T * T;
  o[18] = crit(T, P, &o[14], o[17]);
  o[19] = T + norm2(V) / 3.0;
  return o;
}

void radial_histogram(std::span<const Particle> particles, const HistogramSpec& spec,
                      std::uint64_t* counts) {
  const std::uint64_t K = spec.shells;
  const double scale = static_cast<double>(K) / spec.radius;
  for (const auto& q : particles) {
    const double r = norm(q.v);
    const double k = std::floor(r * scale);
    ++counts[k < static_cast<double>(K) ? static_cast<std::uint64_t>(k) : K];
  }
}

}  // namespace granboltz
