#pragma once
// A random stream's exact state in a checkpoint: the four xoshiro256++ words and the draw count.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "granboltz/h5/hdf5_io.hpp"
#include "granboltz/random/rng.hpp"

namespace granboltz {

inline void write_engine(H5Writer& out, const std::string& path, const Engine& e) {
  const auto& st = e.state();
  out.write(path, std::vector<std::uint64_t>{st[0], st[1], st[2], st[3], e.draws()}, {5});
}

inline Engine read_engine(const H5Reader& in, const std::string& path) {
  if (in.dims(path) != Dims{5})
    throw std::runtime_error(in.path() + ": dataset " + path + ": malformed stream state (not 5 words)");
  const auto v = in.read_uint64(path);
  // The all-zero state is xoshiro256++'s fixed point: it would draw zeros forever, and samplers
  // that reject a zero would never return. make_stream never starts there; only an edit can.
  if ((v[0] | v[1] | v[2] | v[3]) == 0)
    throw std::runtime_error(in.path() + ": dataset " + path +
                             ": a random stream in the all-zero state (a fixed point of "
                             "xoshiro256++), which no run reaches: the file was edited");
  return Engine({v[0], v[1], v[2], v[3]}, v[4]);
}

}  // namespace granboltz
