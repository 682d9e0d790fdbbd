#pragma once
// Particle arrays in a checkpoint: one row (v_x, v_y, v_z, t) per particle, with the weight as a
// fifth column for weighted particles.
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "granboltz/dsmc/particles.hpp"
#include "granboltz/h5/hdf5_io.hpp"

namespace granboltz {

inline void write_particles(H5Writer& out, const std::string& path, const Particles& p,
                            const std::vector<double>* weights = nullptr) {
  const std::size_t n = p.size(), cols = weights ? 5 : 4;
  std::vector<double> rows(cols * n);
  for (std::size_t i = 0; i < n; ++i) {
    double* r = &rows[cols * i];
    r[0] = p[i].v.x, r[1] = p[i].v.y, r[2] = p[i].v.z, r[3] = p[i].t;
    if (weights) r[4] = (*weights)[i];
  }
  out.write(path, rows, {n, cols});
}

/// Reads the rows written by write_particles into p (and weights), resized to their number;
/// false if a value is not finite. An array that is not (n, 4) (weighted: (n, 5)) float64 is
/// refused with a message naming it: an edited file, not a state to guess at.
inline bool read_particles(const H5Reader& in, const std::string& path, Particles& p,
                           std::vector<double>* weights = nullptr) {
  const std::size_t cols = weights ? 5 : 4;
  const Dims dims = in.dims(path);
  if (dims.size() != 2 || dims[1] != cols) {
    std::string shape = "(";
    for (std::size_t k = 0; k < dims.size(); ++k)
      shape += (k ? ", " : "") + std::to_string(dims[k]);
    throw std::runtime_error(in.path() + ": dataset " + path + ": has shape " + shape +
                             (dims.size() == 1 ? ",)" : ")") + ", not (n, " +
                             std::to_string(cols) + ")");
  }
  const auto rows = in.read_double(path);
  const std::size_t n = rows.size() / cols;
  p.resize(n);
  if (weights) weights->resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double* r = &rows[cols * i];
    for (std::size_t k = 0; k < cols; ++k)
      if (!std::isfinite(r[k])) return false;  // a restored state is finite everywhere
    p[i].v = {r[0], r[1], r[2]};
    p[i].t = r[3];
    if (weights) (*weights)[i] = r[4];
  }
  return true;
}

}  // namespace granboltz
