#pragma once
// Order-independent exact summation of doubles. The sum is kept exactly as a fixed-point number
// of 32-bit digits, so adding the same values in any order (any number of threads, any split
// into shards, before or after a restart) gives bit-identical results.
#include <array>
#include <cstdint>
#include <vector>

namespace granboltz {

class ExactSum {
 public:
  static constexpr int kLimbs = 72;     ///< 2304 bits: every finite double and its carries
  static constexpr int kOffset = 1126;  ///< bit position of 2^0 (subnormals start at 2^-1074)

  /// Adds a finite double exactly. Throws std::domain_error for NaN or infinity.
  void add(double x);
  /// Adds another accumulator exactly.
  void merge(const ExactSum& other);
  /// The sum rounded to a double; depends only on the exact value of the sum.
  double value() const;

  /// Canonical digits, for storing an accumulator in a file and merging later.
  std::vector<std::int64_t> digits() const;
  static ExactSum from_digits(const std::vector<std::int64_t>& digits);

 private:
  void normalize();
  std::array<std::int64_t, kLimbs> limb_{};
  std::int64_t pending_ = 0;  // additions since the last carry propagation
};

}  // namespace granboltz
