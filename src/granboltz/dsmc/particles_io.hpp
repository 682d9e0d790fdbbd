#pragma once
// Particle arrays in a checkpoint (record/state_archive.hpp): one row (v_x, v_y, v_z, t) per
// particle, with the weight as a fifth column for weighted particles.
#include <cstdint>
#include <string>
#include <vector>

#include "granboltz/dsmc/particles.hpp"
#include "granboltz/record/state_archive.hpp"

namespace granboltz {

/// The rows of `p` (and `weights`, positive) under `name`: finite, v_z = 0 in dimension 2, their
/// number within `count`. The times are checked against the ensemble's time by the caller (an
/// each() after the time is read).
inline void visit_particles(StateArchive& a, const std::string& name, Particles& p,
                            std::vector<double>* weights, int dimension, const Count& count) {
  const std::size_t cols = weights ? 5 : 4;
  const std::size_t n = a.rows(name, cols, p.size(), count);
  if (a.reading()) {
    p.resize(n);
    if (weights) weights->resize(n);
  }
  a.table<double>(
      name, n, cols,
      {finite(), finite(), zero_if(dimension == 2, "in dimension 2"), finite(), positive()},
      [&](std::size_t i, std::size_t k) {
        return k == 0   ? p[i].v.x
               : k == 1 ? p[i].v.y
               : k == 2 ? p[i].v.z
               : k == 3 ? p[i].t
                        : (*weights)[i];
      },
      [&](std::size_t i, std::size_t k, double x) {
        (k == 0   ? p[i].v.x
         : k == 1 ? p[i].v.y
         : k == 2 ? p[i].v.z
         : k == 3 ? p[i].t
                  : (*weights)[i]) = x;
      });
}

}  // namespace granboltz
