#pragma once
// The particle system of GRW05 §4: velocities in R^3 with the time of their last kick.
#include <vector>

#include "granboltz/vec3.hpp"

namespace granboltz {

/// One particle: 32 bytes, so that a particle never straddles two cache lines.
struct alignas(32) Particle {
  Vec3 v;          ///< velocity
  double t = 0.0;  ///< time of the last kick (sigma_j in RW05 Algorithm 3)
};

using Particles = std::vector<Particle>;

}  // namespace granboltz
