#include "granboltz/dsmc/gas_observables.hpp"

#include <algorithm>
#include <cmath>

namespace granboltz {

Observation measure_gas(const DsmcConfig& d, std::span<const Particle> particles,
                        std::span<const Vec3> spins, std::span<double> moments,
                        const std::vector<double*>& species_rows,
                        const std::vector<double*>& species_moments) {
  const std::size_t n = particles.size(), K = d.species.size();
  Vec3 momentum;
  double total_mass = 0.0, m2 = 0.0;  // sum m, sum m |v|^2
  for (const auto& sp : d.species)
    for (std::uint64_t i = sp.offset; i < sp.offset + sp.count; ++i) {
      momentum += sp.mass * particles[i].v;
      total_mass += sp.mass;
      m2 += sp.mass * norm2(particles[i].v);
    }
  const Vec3 V = (1.0 / total_mass) * momentum;
  Particles c(n);
  for (const auto& sp : d.species) {
    const double root = std::sqrt(sp.mass);
    for (std::uint64_t i = sp.offset; i < sp.offset + sp.count; ++i)
      c[i].v = root * (particles[i].v - V);
  }
  const double dim = static_cast<double>(d.dimension);
  Observation o = measure_about(c, Vec3{}, moments, d.dimension);
  o[1] = V.x, o[2] = V.y, o[3] = V.z;
  o[19] = m2 / (dim * static_cast<double>(n));
  if (d.species_written)
    for (std::size_t a = 0; a < K; ++a) {
      const auto& sp = d.species[a];
      const std::span<const Particle> block(c.data() + sp.offset, sp.count);
      const std::span<double> mm(species_moments[a], static_cast<std::size_t>(d.moments));
      Observation s = measure_about(block, Vec3{}, mm, d.dimension);
      Vec3 mean;
      double v2 = 0.0;
      for (std::uint64_t i = sp.offset; i < sp.offset + sp.count; ++i) {
        mean += particles[i].v;
        v2 += norm2(particles[i].v);
      }
      const double inv = 1.0 / static_cast<double>(sp.count);
      mean = inv * mean;
      s[0] = static_cast<double>(sp.count) / static_cast<double>(n);
      s[1] = mean.x, s[2] = mean.y, s[3] = mean.z;
      s[19] = sp.mass * v2 * inv / dim;
      std::copy(s.begin(), s.end(), species_rows[a]);
    }
  if (d.roughness.on) {
    double e = 0.0;
    for (const auto& sp : d.species) {
      const double I = sp.moment_of_inertia();
      for (std::uint64_t i = sp.offset; i < sp.offset + sp.count; ++i) e += I * norm2(spins[i]);
    }
    const double dof = d.dimension == 2 ? 1.0 : 3.0;
    species_rows.back()[0] = e / (dof * static_cast<double>(n));
  }
  return o;
}

}  // namespace granboltz
