// Samplers against their exact distributions: Kolmogorov-Smirnov and moment tests at fixed seeds.
#include <gsl/gsl_cdf.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <vector>

#include "granboltz/random/rng.hpp"
#include "granboltz/random/samplers.hpp"
#include "test_support.hpp"

using namespace granboltz;

namespace {

/// Kolmogorov-Smirnov statistic sqrt(n) D_n of a sample against a continuous cdf.
double ks_statistic(std::vector<double> x, const std::function<double(double)>& cdf) {
  std::sort(x.begin(), x.end());
  const double n = static_cast<double>(x.size());
  double d = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double F = cdf(x[i]);
    d = std::max({d, F - static_cast<double>(i) / n, static_cast<double>(i + 1) / n - F});
  }
  return std::sqrt(n) * d;
}
// P(sqrt(n) D_n > 1.95) = 0.001 asymptotically (Kolmogorov distribution).
constexpr double kKsCritical = 1.95;

template <class F>
std::vector<double> draw(F f, int n, std::uint64_t ensemble) {
  Engine e = make_stream(2024, ensemble, Consumer::kEvents);
  std::vector<double> x(n);
  for (auto& v : x) v = f(e);
  return x;
}

}  // namespace

TEST(Samplers, NormalFollowsTheGaussianCdf) {
  auto x = draw([](Engine& e) { return normal(e); }, 400000, 1);
  EXPECT_LT(ks_statistic(x, [](double v) { return gsl_cdf_ugaussian_P(v); }), kKsCritical);
}

TEST(Samplers, NormalTailBeyondTheZigguratBaseIsRight) {
  // P(|Z| > 3.5) = 4.65e-4: the tail algorithm must produce it (z ~ Poisson counts).
  Engine e = make_stream(99, 0, Consumer::kEvents);
  const int n = 4000000;
  int count = 0;
  double sum4 = 0;
  for (int i = 0; i < n; ++i) {
    const double z = normal(e);
    count += std::fabs(z) > 3.5;
    sum4 += z * z * z * z;
  }
  const double expected = n * 2 * gsl_cdf_ugaussian_Q(3.5);
  EXPECT_LT(std::fabs(count - expected), test::family_z(2) * std::sqrt(expected));
  // E Z^4 = 3, Var Z^4 = 105 - 9 = 96.
  EXPECT_LT(std::fabs(sum4 / n - 3.0), test::family_z(2) * std::sqrt(96.0 / n));
}

TEST(Samplers, ExponentialFollowsItsCdf) {
  auto x = draw([](Engine& e) { return exponential(e); }, 400000, 2);
  EXPECT_LT(ks_statistic(x, [](double v) { return 1 - std::exp(-v); }), kKsCritical);
  // Beyond the ziggurat base (R = 7.7): P(X > 8) = e^-8 = 3.4e-4.
  const auto tail = std::count_if(x.begin(), x.end(), [](double v) { return v > 8; });
  const double expected = x.size() * std::exp(-8.0);
  EXPECT_LT(std::fabs(tail - expected), test::family_z(1) * std::sqrt(expected));
}

TEST(Samplers, UniformOpenIntervalNeverHitsTheEnds) {
  Engine e = make_stream(3, 0, Consumer::kEvents);
  for (int i = 0; i < 1000000; ++i) {
    const double u = uniform_open01(e);
    ASSERT_GT(u, 0.0);
    ASSERT_LT(u, 1.0);
  }
}

TEST(Samplers, UniformIndexIsUniform) {
  // Chi-square with 6 cells at an awkward range that a biased modulo would skew.
  Engine e = make_stream(4, 0, Consumer::kPairs);
  const std::uint64_t range = 6;
  std::vector<double> counts(range, 0);
  const int n = 600000;
  for (int i = 0; i < n; ++i) {
    const auto k = uniform_index(e, range);
    ASSERT_LT(k, range);
    counts[k] += 1;
  }
  double chi2 = 0;
  for (double c : counts) chi2 += (c - n / 6.0) * (c - n / 6.0) / (n / 6.0);
  EXPECT_LT(chi2, gsl_cdf_chisq_Qinv(0.001, 5));
}

TEST(Samplers, UnitVectorIsUniformOnTheSphere) {
  // For e uniform on S^2: e_z is uniform on [-1, 1] and the azimuth uniform on [0, 2 pi).
  Engine eng = make_stream(5, 0, Consumer::kEvents);
  const int n = 300000;
  std::vector<double> z(n), phi(n);
  for (int i = 0; i < n; ++i) {
    const Vec3 e = unit_vector(eng);
    ASSERT_NEAR(norm(e), 1.0, 1e-14);
    z[i] = e.z;
    phi[i] = std::atan2(e.y, e.x) + M_PI;
  }
  EXPECT_LT(ks_statistic(z, [](double v) { return (v + 1) / 2; }), kKsCritical);
  EXPECT_LT(ks_statistic(phi, [](double v) { return v / (2 * M_PI); }), kKsCritical);
}

TEST(Samplers, KSTestRejectsAWrongDistribution) {
  // The test above can fail: a normal with sd 1.02 is caught.
  auto x = draw([](Engine& e) { return 1.02 * normal(e); }, 400000, 6);
  EXPECT_GT(ks_statistic(x, [](double v) { return gsl_cdf_ugaussian_P(v); }), kKsCritical);
}

TEST(Samplers, NormalPairGivesTwoIndependentNormals) {
  Engine e = make_stream(2024, 7, Consumer::kEvents);
  const int n = 400000;
  std::vector<double> a(n), b(n);
  double sab = 0, tail = 0;
  for (int i = 0; i < n; ++i) {
    normal_pair(e, a[i], b[i]);
    sab += a[i] * b[i];
    tail += (std::fabs(a[i]) > 3.5) + (std::fabs(b[i]) > 3.5);
  }
  auto Phi = [](double v) { return gsl_cdf_ugaussian_P(v); };
  EXPECT_LT(ks_statistic(a, Phi), kKsCritical);
  EXPECT_LT(ks_statistic(b, Phi), kKsCritical);
  // Independence of the halves: E[ab] = 0 with variance 1/n.
  EXPECT_LT(std::fabs(sab / n), test::family_z(2) / std::sqrt(static_cast<double>(n)));
  // The wedges and the tail of the 128-layer ziggurat: P(|Z| > 3.5) = 4.65e-4.
  const double expected = 2.0 * n * 2 * gsl_cdf_ugaussian_Q(3.5);
  EXPECT_LT(std::fabs(tail - expected), test::family_z(2) * std::sqrt(expected));
}

TEST(Samplers, NormalPairMatchesTheGaussianInTheWedges) {
  // A chi-square test on fine bins in [2.5, 4.5], where the wedges and the tail matter most.
  Engine e = make_stream(2024, 8, Consumer::kEvents);
  const int bins = 20;
  std::vector<double> counts(bins, 0);
  const long n = 4000000;
  for (long i = 0; i < n; ++i) {
    double a, b;
    normal_pair(e, a, b);
    for (double v : {std::fabs(a), std::fabs(b)}) {
      const int k = static_cast<int>((v - 2.5) / 0.1);
      if (v >= 2.5 && k < bins) counts[k] += 1;
    }
  }
  double chi2 = 0;
  for (int k = 0; k < bins; ++k) {
    const double lo = 2.5 + 0.1 * k;
    const double p = 2 * (gsl_cdf_ugaussian_Q(lo) - gsl_cdf_ugaussian_Q(lo + 0.1));
    const double expected = 2.0 * n * p;
    chi2 += (counts[k] - expected) * (counts[k] - expected) / expected;
  }
  EXPECT_LT(chi2, gsl_cdf_chisq_Qinv(0.001, bins));
}

namespace {
/// Checks a ziggurat's exp-free wedge decisions against the exp test they replace, on points
/// spread over every wedge and on points within 1e-15..1e-6 of the curve. Returns the fraction
/// of the spread points left undecided (those call exp) in *left.
template <int N>
void check_wedges(const detail::ZigguratTables<N>& z, double (*f)(double), const char* name,
                  double* left) {
  Engine eng = make_stream(2024, 0, Consumer::kEvents);
  std::uint64_t spread = 0, undecided = 0;
  for (unsigned i = 1; i < static_cast<unsigned>(N); ++i) {
    for (int k = 0; k < 2000; ++k) {
      const double ax = z.x[i + 1] + uniform01(eng) * (z.x[i] - z.x[i + 1]);
      const double y = z.f[i] + uniform01(eng) * (z.f[i + 1] - z.f[i]);
      const int quick = z.wedge(i, ax, y);
      ++spread;
      if (quick == 0)
        ++undecided;
      else
        ASSERT_EQ(quick > 0, y < f(ax)) << name << " layer " << i << " x " << ax << " y " << y;
      for (const double d : {1e-15, 1e-12, 1e-9, 1e-6}) {
        for (const double yy : {f(ax) * (1 - d), f(ax) * (1 + d)}) {
          const int q = z.wedge(i, ax, yy);
          if (q != 0) ASSERT_EQ(q > 0, yy < f(ax)) << name << " layer " << i << " x " << ax;
        }
      }
    }
  }
  *left = static_cast<double>(undecided) / static_cast<double>(spread);
}
double normal_density(double x) { return std::exp(-0.5 * x * x); }
double exponential_density(double x) { return std::exp(-x); }
}  // namespace

TEST(Samplers, ZigguratWedgesDecideWithoutExpAsExpWould) {
  // The chord bounds must never contradict the exp test (else the variates would change); they
  // should leave it a small part of the wedge tests (else they do not pay).
  double n256 = 1, n128 = 1, e256 = 1;
  check_wedges(detail::kNormalZiggurat, normal_density, "normal256", &n256);
  check_wedges(detail::kNormalZiggurat128, normal_density, "normal128", &n128);
  check_wedges(detail::kExponentialZiggurat, exponential_density, "exp256", &e256);
  std::printf("wedge points left to exp: normal %.4f (256), %.4f (128), exponential %.4f\n", n256,
              n128, e256);
  EXPECT_LT(n256, 0.05);
  EXPECT_LT(n128, 0.05);
  EXPECT_LT(e256, 0.05);
}
