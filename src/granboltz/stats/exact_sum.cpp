#include "granboltz/stats/exact_sum.hpp"

#include <cmath>
#include <stdexcept>

#include "granboltz/core/int128.hpp"

namespace granboltz {

namespace {
// Each limb receives digits below 2^32 per addition; normalizing well before 2^31 additions
// keeps the int64 limbs from overflowing.
constexpr std::int64_t kNormalizeEvery = std::int64_t{1} << 29;
}  // namespace

void ExactSum::add(double x) {
  if (!std::isfinite(x)) throw std::domain_error("ExactSum: non-finite value");
  if (x == 0.0) return;
  int e = 0;
  const double m = std::frexp(x, &e);                              // x = m 2^e, 0.5 <= |m| < 1
  const auto mant = static_cast<std::int64_t>(std::ldexp(m, 53));  // exact, |mant| < 2^53
  const int p = e - 53 + kOffset;                                  // x = mant * 2^(p - kOffset)
  const int idx = p / 32;
  const int sh = p % 32;
  const bool negative = mant < 0;
  const uint128 a = static_cast<uint128>(negative ? -mant : mant) << sh;
  const auto d0 = static_cast<std::int64_t>(a & 0xFFFFFFFFu);
  const auto d1 = static_cast<std::int64_t>((a >> 32) & 0xFFFFFFFFu);
  const auto d2 = static_cast<std::int64_t>(a >> 64);
  if (negative) {
    limb_[idx] -= d0;
    limb_[idx + 1] -= d1;
    limb_[idx + 2] -= d2;
  } else {
    limb_[idx] += d0;
    limb_[idx + 1] += d1;
    limb_[idx + 2] += d2;
  }
  if (++pending_ >= kNormalizeEvery) normalize();
}

void ExactSum::normalize() {
  for (int k = 0; k + 1 < kLimbs; ++k) {
    const std::int64_t carry = limb_[k] >> 32;  // floor division by 2^32
    limb_[k] -= carry * (std::int64_t{1} << 32);
    limb_[k + 1] += carry;
  }
  pending_ = 0;
}

void ExactSum::merge(const ExactSum& other) {
  ExactSum b = other;
  b.normalize();
  normalize();
  for (int k = 0; k < kLimbs; ++k) limb_[k] += b.limb_[k];
  normalize();
}

double ExactSum::value() const {
  ExactSum c = *this;
  c.normalize();
  // A negative sum is stored like a two's complement (top digits all ones): convert its negation.
  const bool negative = c.limb_[kLimbs - 1] < 0;
  if (negative) {
    for (auto& d : c.limb_) d = -d;
    c.normalize();
  }
  int top = kLimbs - 1;
  while (top >= 0 && c.limb_[top] == 0) --top;
  if (top < 0) return 0.0;
  // Digits below the top one are in [0, 2^32): four digits carry more than 96 bits.
  double r = 0.0;
  for (int k = top; k >= 0 && k >= top - 3; --k)
    r += std::ldexp(static_cast<double>(c.limb_[k]), 32 * k - kOffset);
  return negative ? -r : r;
}

std::vector<std::int64_t> ExactSum::digits() const {
  ExactSum c = *this;
  c.normalize();
  return {c.limb_.begin(), c.limb_.end()};
}

ExactSum ExactSum::from_digits(const std::vector<std::int64_t>& digits) {
  if (digits.size() != static_cast<std::size_t>(kLimbs))
    throw std::invalid_argument("ExactSum: wrong number of digits");
  ExactSum s;
  for (int k = 0; k < kLimbs; ++k) s.limb_[k] = digits[k];
  s.normalize();
  return s;
}

}  // namespace granboltz
