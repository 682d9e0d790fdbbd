#include "granboltz/stats/statistics.hpp"

#include <algorithm>
#include <cmath>

namespace granboltz {

MeanCi Moments2::stats(std::uint64_t count) const {
  MeanCi r;
  if (count == 0) return r;
  const double n = static_cast<double>(count);
  r.mean = sum.value() / n;
  r.variance = std::max(0.0, sum_sq.value() / n - r.mean * r.mean);
  r.ci = kLambdaP * std::sqrt(r.variance / n);
  return r;
}

}  // namespace granboltz
