#pragma once
// How a restitution law declares its parameters: the config layer reads, checks and emits them
// from this table, so a law's header stays free of YAML and I/O.

namespace granboltz {

template <class Law>
struct LawParam {
  const char* key;     ///< its key inside dsmc.restitution
  double Law::*value;  ///< the member it sets
  double min;          ///< allowed: min < value (min_open) or min <= value
  bool min_open;
  double max;  ///< allowed: value <= max (or < max with max_open)
  bool max_open;
  const char* allowed;  ///< the one-line text of a refusal, e.g. "must be >= 0"

  constexpr bool ok(double v) const {
    return (min_open ? v > min : v >= min) && (max_open ? v < max : v <= max);
  }
};

}  // namespace granboltz
