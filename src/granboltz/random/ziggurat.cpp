// Ziggurat tables for samplers.hpp. The base-layer edge R is found with GSL's Brent solver so
// that the 256 layers of equal area V close exactly at the top (x[256] = 0), instead of relying
// on the rounded constants printed by Marsaglia & Tsang.
#include <gsl/gsl_errno.h>
#include <gsl/gsl_roots.h>

#include <algorithm>
#include <cmath>
#include <new>
#include <stdexcept>
#include <string>

#include "granboltz/core/gsl_errors.hpp"
#include "granboltz/random/samplers.hpp"

namespace granboltz::detail {
namespace {

struct Shape {
  double (*f)(double);     // decreasing density shape on [0, inf)
  double (*finv)(double);  // its inverse on (0, 1]
  double (*tail)(double);  // integral of f from R to infinity
};

double normal_f(double x) { return std::exp(-0.5 * x * x); }
double normal_finv(double y) { return std::sqrt(-2.0 * std::log(y)); }
double normal_tail(double r) { return std::sqrt(M_PI / 2.0) * std::erfc(r / std::sqrt(2.0)); }
double exp_f(double x) { return std::exp(-x); }
double exp_finv(double y) { return -std::log(y); }
double exp_tail(double r) { return std::exp(-r); }

// Builds the layers for base edge r; returns how far the top layer misses closing the ziggurat
// (zero at the right r, negative when the layers run out early).
template <int N>
double build(const Shape& s, double r, ZigguratTables<N>* z) {
  const double v = r * s.f(r) + s.tail(r);
  z->x[0] = v / s.f(r);
  z->x[1] = r;
  for (int i = 1; i < N - 1; ++i) {
    const double y = v / z->x[i] + s.f(z->x[i]);
    if (y >= 1.0) return -(N - i);
    z->x[i + 1] = s.finv(y);
  }
  z->x[N] = 0.0;
  return 1.0 - (v / z->x[N - 1] + s.f(z->x[N - 1]));
}

template <int N>
ZigguratTables<N> make(const Shape& s, double lo, double hi) {
  ZigguratTables<N> z{};
  struct Ctx {
    const Shape* s;
    ZigguratTables<N>* z;
  } ctx{&s, &z};
  gsl_function fn;
  fn.function = [](double r, void* p) {
    auto* c = static_cast<Ctx*>(p);
    return build(*c->s, r, c->z);
  };
  fn.params = &ctx;
  install_gsl_error_handler();
  gsl_root_fsolver* solver = gsl_root_fsolver_alloc(gsl_root_fsolver_brent);
  if (!solver) throw std::bad_alloc();
  int status = gsl_root_fsolver_set(solver, &fn, lo, hi);
  double r = lo;
  for (int iter = 0; status == GSL_SUCCESS && iter < 200; ++iter) {
    status = gsl_root_fsolver_iterate(solver);
    r = gsl_root_fsolver_root(solver);
    if (gsl_root_test_interval(gsl_root_fsolver_x_lower(solver), gsl_root_fsolver_x_upper(solver),
                               0.0, 1e-15) == GSL_SUCCESS)
      break;
  }
  gsl_root_fsolver_free(solver);
  // Fixed shapes and brackets: a failure here is a bug, reported rather than aborting.
  if (status != GSL_SUCCESS)
    throw std::runtime_error("ziggurat tables: root finder failed (" + describe_gsl_status(status) +
                             ")");
  build(s, r, &z);
  for (int i = 0; i <= N; ++i) z.f[i] = s.f(z.x[i]);
  for (int i = 0; i < N; ++i) z.ratio[i] = z.x[i + 1] / z.x[i];
  // Chords of the wedges and the range of f - chord over each, from a dense grid (f is smooth
  // with at most one inflection per layer: the grid finds the extremes to a relative 1e-4, and
  // they are widened by 1 % and a margin). Layer 0 (the base strip and tail) has no wedge test.
  constexpr int kGrid = 256;
  constexpr double kMargin = 1e-13;
  for (int i = 1; i < N; ++i) {
    const double a = z.x[i + 1], b = z.x[i];
    z.slope[i] = (z.f[i + 1] - z.f[i]) / (a - b);
    double gap_min = 0.0, gap_max = 0.0;
    for (int k = 0; k <= kGrid; ++k) {
      const double xk = a + (b - a) * k / kGrid;
      const double gap = s.f(xk) - (z.f[i] + z.slope[i] * (xk - b));
      gap_min = std::min(gap_min, gap);
      gap_max = std::max(gap_max, gap);
    }
    z.below[i] = 1.01 * gap_min - kMargin;
    z.above[i] = 1.01 * gap_max + kMargin;
  }
  z.slope[0] = z.below[0] = z.above[0] = 0.0;
  return z;
}

}  // namespace

const ZigguratTables<256> kNormalZiggurat =
    make<256>({normal_f, normal_finv, normal_tail}, 3.0, 4.5);
const ZigguratTables<128> kNormalZiggurat128 =
    make<128>({normal_f, normal_finv, normal_tail}, 2.8, 4.2);
const ZigguratTables<256> kExponentialZiggurat = make<256>({exp_f, exp_finv, exp_tail}, 6.0, 9.0);

}  // namespace granboltz::detail
