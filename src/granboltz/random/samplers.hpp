#pragma once
// Samplers: small pure functions templated on a 64-bit engine (result_type = uint64_t).
// No allocation, no I/O. Gaussian and exponential variates use 256-layer ziggurats
// (Marsaglia & Tsang, J. Stat. Softw. 5(8), 2000), whose tables are built once (ziggurat.cpp).
#include <cmath>
#include <cstdint>

#include "granboltz/core/hot.hpp"
#include "granboltz/core/int128.hpp"
#include "granboltz/core/vec3.hpp"

namespace granboltz {

namespace detail {
template <int N>
struct ZigguratTables {
  double x[N + 1];  ///< layer edges, x[0] = V/f(R) > x[1] = R > ... > x[N] = 0
  double f[N + 1];  ///< f(x[i])
  double ratio[N];  ///< x[i+1]/x[i]: the fraction of layer i inside the density
  // The wedge of layer i (x[i+1] <= |x| < x[i]) decided without exp: the chord through its
  // corners, L(x) = f[i] + slope[i] (|x| - x[i]), and bounds of f - L over the layer, widened by a
  // margin far above rounding (1e-13, against errors of order 1e-16 in L and in libm's exp). A
  // point below L + below[i] is under f, one at or above L + above[i] is not: the decision that
  // `y < exp(...)` would take, so the variates are the same bits, with exp called only in the
  // narrow band between (0.4-0.7 % of the wedge tests instead of all of them).
  double slope[N];
  double below[N];
  double above[N];

  /// +1: y is certainly under the density at |x| = ax (accept), -1: certainly not (reject),
  /// 0: call exp.
  int wedge(unsigned i, double ax, double y) const {
    const double chord = f[i] + slope[i] * (ax - x[i]);
    if (y < chord + below[i]) return 1;
    if (y >= chord + above[i]) return -1;
    return 0;
  }
  /// The wedge test y < f(x): by wedge() where it decides, else by exact() (the exp).
  template <class F>
  bool under(unsigned i, double ax, double y, F exact) const {
    const int quick = wedge(i, ax, y);
    return quick > 0 || (quick == 0 && y < exact());
  }
};
extern const ZigguratTables<256> kNormalZiggurat;       // f(x) = exp(-x^2/2)
extern const ZigguratTables<128> kNormalZiggurat128;    // the same with 128 layers
extern const ZigguratTables<256> kExponentialZiggurat;  // f(x) = exp(-x)
}  // namespace detail

/// Uniform on [0, 1) with 53 random bits.
template <class E>
inline double uniform01(E& eng) {
  return static_cast<double>(eng() >> 11) * 0x1.0p-53;
}

/// Uniform on the open interval (0, 1): never 0, so its logarithm is finite.
template <class E>
inline double uniform_open01(E& eng) {
  return (static_cast<double>(eng() >> 11) + 0.5) * 0x1.0p-53;
}

/// Uniform integer in [0, range), range >= 1, without bias (Lemire, ACM TOMS 2019).
template <class E>
inline std::uint64_t uniform_index(E& eng, std::uint64_t range) {
  uint128 m = static_cast<uint128>(eng()) * range;
  auto low = static_cast<std::uint64_t>(m);
  if (low < range) {
    const std::uint64_t threshold = (0 - range) % range;
    while (low < threshold) {
      m = static_cast<uint128>(eng()) * range;
      low = static_cast<std::uint64_t>(m);
    }
  }
  return static_cast<std::uint64_t>(m >> 64);
}

/// Two independent uniform indices in [0, range_a) and [0, range_b) from one 64-bit draw, each
/// from 32 bits by Lemire's method with its exact rejection step (ranges below 2^32).
template <class E>
inline void uniform_index_pair(E& eng, std::uint32_t range_a, std::uint32_t range_b,
                               std::uint32_t& a, std::uint32_t& b) {
  for (;;) {
    const std::uint64_t bits = eng();
    const std::uint64_t ma = (bits >> 32) * range_a;
    const std::uint64_t mb = (bits & 0xFFFFFFFFu) * range_b;
    // Rejection is needed only when a low part falls below 2^32 mod range: rare for small ranges.
    if (static_cast<std::uint32_t>(ma) < range_a &&
        static_cast<std::uint32_t>(ma) < static_cast<std::uint32_t>(-range_a) % range_a)
      continue;
    if (static_cast<std::uint32_t>(mb) < range_b &&
        static_cast<std::uint32_t>(mb) < static_cast<std::uint32_t>(-range_b) % range_b)
      continue;
    a = static_cast<std::uint32_t>(ma >> 32);
    b = static_cast<std::uint32_t>(mb >> 32);
    return;
  }
}

namespace detail {
/// Normal tail beyond r (Marsaglia 1964), with the sign of `negative`.
template <class E>
inline double normal_tail(double r, bool negative, E& eng) {
  double xt, yt;
  do {
    xt = -std::log(uniform_open01(eng)) / r;
    yt = -std::log(uniform_open01(eng));
  } while (yt + yt < xt * xt);
  return negative ? -(r + xt) : r + xt;
}

}  // namespace detail

/// Standard normal variate (ziggurat).
template <class E>
inline double normal(E& eng) {
  const auto& z = detail::kNormalZiggurat;
  for (;;) {
    const std::uint64_t bits = eng();
    const unsigned layer = bits & 0xFF;
    // Signed uniform on [-1, 1) from the top 53 bits.
    const double u = static_cast<double>(static_cast<std::int64_t>(bits) >> 11) * 0x1.0p-52;
    if (std::fabs(u) < z.ratio[layer]) return u * z.x[layer];
    if (layer == 0) return detail::normal_tail(z.x[1], u < 0, eng);
    const double x = u * z.x[layer];
    const double y = z.f[layer] + uniform01(eng) * (z.f[layer + 1] - z.f[layer]);
    if (z.under(layer, std::fabs(x), y, [x] { return std::exp(-0.5 * x * x); })) return x;
  }
}

namespace detail {
/// The rare part of a 128-layer ziggurat attempt that the inner rectangles did not accept: the
/// tail below the base layer, or the wedge test. A rejected attempt restarts, and since any
/// restart yields an exact normal variate, it is drawn by normal().
template <class E>
[[gnu::noinline]] double normal128_slow(unsigned layer, double u, E& eng) {
  const auto& z = kNormalZiggurat128;
  if (layer == 0) return normal_tail(z.x[1], u < 0, eng);
  const double x = u * z.x[layer];
  const double y = z.f[layer] + uniform01(eng) * (z.f[layer + 1] - z.f[layer]);
  if (z.under(layer, std::fabs(x), y, [x] { return std::exp(-0.5 * x * x); })) return x;
  return normal(eng);
}

/// One attempt of the 128-layer ziggurat on 32 random bits: the layer from the low 7 bits, the
/// signed abscissa from the other 25 (a resolution of 2^-24 of the layer width, as in Marsaglia
/// & Tsang's 32-bit original, but with disjoint bits for layer and value after Doornik 2005).
/// 98.8% of attempts end in the inner rectangles.
template <class E>
inline double normal_from32(std::uint32_t bits, E& eng) {
  const auto& z = kNormalZiggurat128;
  const unsigned layer = bits & 127u;
  const double u = static_cast<double>(static_cast<std::int32_t>(bits & ~127u)) * 0x1.0p-31;
  if (std::fabs(u) < z.ratio[layer]) [[likely]]
    return u * z.x[layer];
  return normal128_slow(layer, u, eng);
}
}  // namespace detail

/// Two independent standard normal variates from (usually) one 64-bit draw.
template <class E>
GRANBOLTZ_HOT void normal_pair(E& eng, double& a, double& b) {
  const std::uint64_t bits = eng();
  a = detail::normal_from32(static_cast<std::uint32_t>(bits >> 32), eng);
  b = detail::normal_from32(static_cast<std::uint32_t>(bits), eng);
}

/// Exponential variate with rate 1 (ziggurat).
template <class E>
GRANBOLTZ_HOT double exponential(E& eng) {
  const auto& z = detail::kExponentialZiggurat;
  double offset = 0.0;
  for (;;) {
    const std::uint64_t bits = eng();
    const unsigned layer = bits & 0xFF;
    const double u = static_cast<double>(bits >> 11) * 0x1.0p-53;
    if (u < z.ratio[layer]) return offset + u * z.x[layer];
    if (layer == 0) {
      // Memoryless tail: beyond R the density is again exponential.
      offset += z.x[1];
      continue;
    }
    const double x = u * z.x[layer];
    const double y = z.f[layer] + uniform01(eng) * (z.f[layer + 1] - z.f[layer]);
    if (z.under(layer, x, y, [x] { return std::exp(-x); })) return offset + x;
  }
}

/// Vector of three independent standard normals.
template <class E>
inline Vec3 normal3(E& eng) {
  const double a = normal(eng);
  const double b = normal(eng);
  const double c = normal(eng);
  return {a, b, c};
}

/// A point (a, b) of the square (-1, 1)^2 from one 64-bit draw, 32 random bits a coordinate
/// (centred in their cells: never 0 or +-1); the trial of the rejection samplers below.
GRANBOLTZ_HOT void square_point(std::uint64_t bits, double& a, double& b) {
  a = static_cast<double>(static_cast<std::int32_t>(bits >> 32)) * 0x1.0p-31 + 0x1.0p-32;
  b = static_cast<double>(static_cast<std::int32_t>(bits)) * 0x1.0p-31 + 0x1.0p-32;
}

/// Uniform direction on S^2 without trigonometry (Marsaglia, Ann. Math. Stat. 43, 1972). Each
/// trial takes both coordinates, with 32 random bits each, from one 64-bit draw.
template <class E>
GRANBOLTZ_HOT Vec3 unit_vector(E& eng) {
  for (;;) {
    double a, b;
    square_point(eng(), a, b);
    const double s = a * a + b * b;
    if (s < 1.0) {
      const double w = 2.0 * std::sqrt(1.0 - s);
      return {a * w, b * w, 1.0 - 2.0 * s};
    }
  }
}

}  // namespace granboltz
