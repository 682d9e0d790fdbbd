// TV06 baths: closed-form fluxes against GSL quadrature of their definitions (eqs. 5-7), the
// densities' normalization and temperature, and every sampler against its density (KS).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "granboltz/random/rng.hpp"
#include "granboltz/tv06/bath.hpp"
#include "tv06_support.hpp"

using namespace granboltz;
using namespace granboltz::tv06;
using namespace granboltz::tv06test;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// phi_+(v1) = rho ∫_{-inf}^{v1} (v1 - v) f dv and phi_-(v1) = rho ∫_{v1}^{inf} (v - v1) f dv.
template <class B>
Fluxes fluxes_by_quadrature(const B& bath, double v1) {
  auto plus = [&](double v) { return (v1 - v) * bath.pdf(v); };
  auto minus = [&](double v) { return (v - v1) * bath.pdf(v); };
  return {bath.density() * integrate(plus, -kInf, v1), bath.density() * integrate(minus, v1, kInf)};
}

template <class B>
void expect_fluxes_match(const B& bath, const char* name) {
  for (double v1 : {-6.0, -3.0, -1.3, -0.4, -1e-7, 0.0, 1e-7, 0.25, 0.9, 2.0, 4.5, 8.0}) {
    const Fluxes f = bath.fluxes(v1), q = fluxes_by_quadrature(bath, v1);
    EXPECT_NEAR(f.plus, q.plus, 1e-11 * q.plus + 1e-300) << name << " v1=" << v1;
    EXPECT_NEAR(f.minus, q.minus, 1e-11 * q.minus + 1e-300) << name << " v1=" << v1;
    // Eq. 15: phi_+ - phi_- = rho v1 (momentum balance of the two fluxes).
    EXPECT_NEAR(f.plus - f.minus, bath.density() * v1, 1e-13 * f.total()) << name;
  }
}

}  // namespace

TEST(TV06Bath, GaussianFluxesMatchQuadratureAndEquation15) {
  for (double a : {0.5, 1.0, 2.0, 4.0})
    for (double rho : {1.0, 2.5}) {
      const GaussianBath bath = gaussian_bath(a, rho);
      expect_fluxes_match(bath, "gaussian");
      // TV06 eq. 15 as printed.
      for (double v1 : {-2.0, -0.5, 0.0, 0.7, 3.0}) {
        const double e = std::exp(-a * v1 * v1) / std::sqrt(M_PI * a);
        const double erf = std::erf(v1 * std::sqrt(a));
        EXPECT_NEAR(bath.fluxes(v1).plus, rho / 2 * (v1 + e + v1 * erf), 1e-14 * rho * (1 + e));
        EXPECT_NEAR(bath.fluxes(v1).minus, rho / 2 * (-v1 + e + v1 * erf), 1e-14 * rho * (1 + e));
      }
    }
}

TEST(TV06Bath, GaussianTailFluxKeepsItsRelativeAccuracy) {
  // k(c) = ∫_c^∞ (y - c) p(y) dy = p(c) ∫_0^∞ s exp(-c s - s^2/2) ds (y = c + s): no cancellation.
  // Tolerance: the rounding of the exponent of p(c) alone gives a relative error ~ c^2 eps / 2.
  for (double c : {2.9, 3.0, 3.9, 4.0, 4.1, 6.0, 7.9, 8.0, 12.0, 25.0, 37.0}) {
    const double q =
        GaussianShape::pdf(c) *
        integrate([&](double s) { return s * std::exp(-c * s - 0.5 * s * s); }, 0, kInf);
    EXPECT_NEAR(GaussianShape::tail_flux(c), q, 2e-15 * (1 + c * c) * q) << "c=" << c;
  }
}

TEST(TV06Bath, PowerLawFluxesMatchQuadrature) {
  for (double a : {0.5, 1.0, 2.0, 4.0}) expect_fluxes_match(power_law_bath(a, 1.0), "powerlaw");
  expect_fluxes_match(power_law_bath(1.0, 3.0), "powerlaw rho=3");
  // Far tails, where the closed form must keep its relative accuracy: the defining integral
  // with y = 1/s, ∫_0^(1/c) (1/s - c) p(1/s) / s^2 ds, on a finite interval.
  for (double c : {5.0, 20.0, 1e3, 1e5}) {
    const double k = PowerLawShape::tail_flux(c);
    const double q = integrate(
        [&](double s) { return s == 0 ? 0.0 : (1 / s - c) * PowerLawShape::pdf(1 / s) / (s * s); },
        0, 1 / c);
    EXPECT_NEAR(k, q, 1e-12 * q) << "c=" << c;
  }
}

TEST(TV06Bath, PowerLawSurvivalMatchesQuadrature) {
  for (double y :
       {-30.0, -2.0, -1.0, -0.3, 0.0, 0.4, 0.999, 1.0, 1.5, 1.999, 2.0, 2.2, 7.0, 1e3, 1e6}) {
    // For y > 1 the tail integral with t = 1/s: ∫_0^(1/y) p(1/s) / s^2 ds.
    auto tail = [](double s) { return s == 0 ? 0.0 : PowerLawShape::pdf(1 / s) / (s * s); };
    const double q = y > 1 ? integrate(tail, 0, 1 / y) : integrate(PowerLawShape::pdf, y, kInf);
    EXPECT_NEAR(PowerLawShape::survival(y), q, 1e-13 * q) << "y=" << y;
  }
}

TEST(TV06Bath, DensitiesAreNormalizedAndHaveTheStatedTemperature) {
  // TV06 says <v^2> = 1/a for the power law; quadrature confirms it (and 1/(2a) for the Gaussian).
  for (double a : {0.3, 1.0, 5.0}) {
    const GaussianBath g = gaussian_bath(a, 1.0);
    const PowerLawBath p = power_law_bath(a, 1.0);
    EXPECT_NEAR(integrate([&](double v) { return g.pdf(v); }, -kInf, kInf), 1.0, 1e-13);
    EXPECT_NEAR(integrate([&](double v) { return p.pdf(v); }, -kInf, kInf), 1.0, 1e-13);
    const double g2 = integrate([&](double v) { return v * v * g.pdf(v); }, -kInf, kInf);
    const double p2 = integrate([&](double v) { return v * v * p.pdf(v); }, -kInf, kInf);
    EXPECT_NEAR(g2, 1.0 / (2 * a), 1e-12 / a);
    EXPECT_NEAR(p2, 1.0 / a, 1e-10 / a);
    EXPECT_DOUBLE_EQ(g.temperature(), 1.0 / (2 * a));
    EXPECT_DOUBLE_EQ(p.temperature(), 1.0 / a);
    // TV06 eq. 19 as printed.
    EXPECT_NEAR(p.pdf(0.7), std::sqrt(2 * a) / M_PI / (1 + a * a * std::pow(0.7, 4)), 1e-15);
    EXPECT_NEAR(g.pdf(0.7), std::sqrt(a / M_PI) * std::exp(-a * 0.49), 1e-15);
  }
  EXPECT_NEAR(GaussianShape::kHalfMoment,
              integrate([](double y) { return y * GaussianShape::pdf(y); }, 0, kInf), 1e-15);
  EXPECT_NEAR(PowerLawShape::kHalfMoment,
              integrate([](double y) { return y * PowerLawShape::pdf(y); }, 0, kInf), 1e-15);
}

TEST(TV06Bath, BathSamplersFollowTheirDensities) {
  const int n = 100000, checks = 2;
  {
    Engine e = make_stream(606, 0, Consumer::kBath);
    const PowerLawBath bath = power_law_bath(2.0, 1.0);
    std::vector<double> x(n);
    for (auto& v : x) v = bath.sample(e);
    EXPECT_LT(ks_statistic(
                  x, [&](double v) { return bath.pdf(v); }, -kInf, kInf),
              ks_critical(checks));
  }
  {
    Engine e = make_stream(606, 1, Consumer::kBath);
    const GaussianBath bath = gaussian_bath(0.7, 1.0);
    std::vector<double> x(n);
    for (auto& v : x) v = bath.sample(e);
    EXPECT_LT(ks_statistic(
                  x, [&](double v) { return bath.pdf(v); }, -kInf, kInf),
              ks_critical(checks));
  }
}

namespace {

/// KS of the colliding velocity on `side` of a surface at v1 against g_+- (eqs. 12-13).
template <class B>
void expect_colliding_sampler_exact(const B& bath, std::uint64_t stream, int checks,
                                    const char* name) {
  const int n = 50000;
  int k = 0;
  for (double v1 : {-3.0, -1.0, -0.2, 0.0, 0.3, 1.2, 3.0}) {
    for (Side side : {Side::kPlus, Side::kMinus}) {
      Engine e = make_stream(stream, static_cast<std::uint64_t>(k++), Consumer::kIntruder);
      std::vector<double> x(n);
      for (auto& v : x) v = bath.sample_colliding(e, v1, side);
      const bool plus = side == Side::kPlus;
      for (double v : x) ASSERT_TRUE(plus ? v <= v1 : v >= v1) << name;
      auto g = [&](double v) { return (plus ? v1 - v : v - v1) * bath.pdf(v); };
      EXPECT_LT(plus ? ks_statistic(x, g, -kInf, v1) : ks_statistic(x, g, v1, kInf),
                ks_critical(checks))
          << name << " v1=" << v1 << (plus ? " side +" : " side -");
    }
  }
}

}  // namespace

TEST(TV06Bath, CollidingVelocitySamplersFollowG) {
  // 7 velocities x 2 sides x 2 parameters x 2 baths.
  const int checks = 56;
  for (double a : {0.5, 2.0}) {
    expect_colliding_sampler_exact(gaussian_bath(a, 1.0), 700 + static_cast<int>(a * 10), checks,
                                   "gaussian");
    expect_colliding_sampler_exact(power_law_bath(a, 1.0), 800 + static_cast<int>(a * 10), checks,
                                   "powerlaw");
  }
}

TEST(TV06Bath, CollidingVelocityTailsAreNotTruncated) {
  // The far tails of g_+- carry mass that TV06's sampling windows cut off (about 3e-5 of it
  // for the first two cases); count the samples there (binomial counts, normal approximation,
  // sample sizes giving >= 250 expected counts).
  struct Case {
    bool gaussian;
    double v1;
    Side side;
    double beyond;  // count samples with |v - v1| > beyond
  };
  const Case cases[] = {{true, 2.0, Side::kPlus, 5.0},   // outside TV06's window -3 <= v <= 3
                        {true, -2.0, Side::kPlus, 2.0},  // outside v1 - 2 <= v <= v1
                        {true, -1.0, Side::kPlus, 2.0},    {false, 0.5, Side::kPlus, 30.0},
                        {false, -1.0, Side::kMinus, 30.0}, {false, 2.0, Side::kMinus, 100.0}};
  const int checks = 6;
  const double z = gsl_cdf_ugaussian_Qinv(0.5 * kLevel / checks);
  int k = 0;
  for (const Case& c : cases) {
    Engine e = make_stream(909, static_cast<std::uint64_t>(k++), Consumer::kIntruder);
    const GaussianBath g = gaussian_bath(1.0, 1.0);
    const PowerLawBath p = power_law_bath(1.0, 1.0);
    auto pdf = [&](double v) { return c.gaussian ? g.pdf(v) : p.pdf(v); };
    const bool plus = c.side == Side::kPlus;
    auto dens = [&](double v) { return (plus ? c.v1 - v : v - c.v1) * pdf(v); };
    const double total = plus ? integrate(dens, -kInf, c.v1) : integrate(dens, c.v1, kInf);
    const double tail =
        plus ? integrate(dens, -kInf, c.v1 - c.beyond) : integrate(dens, c.v1 + c.beyond, kInf);
    const double prob = tail / total;
    const long n = std::min(10000000L, static_cast<long>(300 / prob));
    long count = 0;
    for (long i = 0; i < n; ++i) {
      const double v =
          c.gaussian ? g.sample_colliding(e, c.v1, c.side) : p.sample_colliding(e, c.v1, c.side);
      count += std::fabs(v - c.v1) > c.beyond;
    }
    const double expected = static_cast<double>(n) * prob;
    ASSERT_GT(expected, 250.0);
    EXPECT_LT(std::fabs(static_cast<double>(count) - expected),
              z * std::sqrt(expected * (1 - prob)))
        << "case " << k << ": expected " << expected << ", got " << count;
  }
}
