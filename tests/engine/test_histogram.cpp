// The speed histograms of a heated run integrate to the moments measured on the same particles:
// about the bulk velocity to the centred second moment 3T, about the origin to <|v|^2>, and the
// component histogram of (v - V)_x to 0 and P_xx. Binning moves a particle's r^2 by at most
// h r + h^2/4 (h the bin width), so the bounds are exact, not statistical.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "granboltz/app/config.hpp"
#include "granboltz/dsmc/run.hpp"
#include "test_support.hpp"

using namespace granboltz;

namespace {

// White noise makes the bulk velocity random-walk: E|V|^2 = 6 beta t / n = 0.3 at t = 10, summed
// over the 4 ensembles a chi-square of 12 degrees of freedom.
const char* kHeated = R"(model: dsmc
seed: 3
ensembles: 4
dsmc:
  particles: 200
  alpha: 0.7
  beta: 1
  kernel: {lambda: 1, C: 1}
  t_end: 10
  observe_every: 1
  histogram: {shells: 2000, radius: 12, component: true}
  moments: 2
)";

struct Integrals {
  double m0, m1, m2;  // sum_k f_k, sum_k f_k x_k, sum_k f_k x_k^2 at the bin midpoints x_k
  std::uint64_t overflow;
};

Integrals integrate(const Record& record, const std::string& name, std::uint64_t row,
                    const DsmcConfig& d, std::uint64_t N, double first_edge, double width) {
  const std::uint64_t K1 = d.histogram.shells + 1;
  const auto& counts = record.counts(name);
  Integrals r{0, 0, 0, counts[row * K1 + K1 - 1]};
  const double norm = static_cast<double>(d.particles) * static_cast<double>(N);
  for (std::uint64_t k = 0; k + 1 < K1; ++k) {
    const double f = static_cast<double>(counts[row * K1 + k]) / norm;
    const double x = first_edge + (static_cast<double>(k) + 0.5) * width;
    r.m0 += f;
    r.m1 += f * x;
    r.m2 += f * x * x;
  }
  return r;
}

}  // namespace

TEST(Histogram, AboutTheBulkVelocityIntegratesToTheCentredMoments) {
  for (const char* center : {"bulk", "origin"}) {
    const Config c =
        parse_config(kHeated, "test.yaml", {std::string("dsmc.histogram.center=") + center});
    const test::DsmcRun run(c);
    const DsmcConfig& d = c.dsmc;
    const double h = d.histogram.radius / static_cast<double>(d.histogram.shells);
    double largest_shift = 0.0;
    for (std::uint64_t m = 0; m < run.times.size(); ++m) {
      const double T = run.at(m, 4).mean, T_total = run.at(m, 19).mean, Pxx = run.at(m, 5).mean;
      // bulk: <|v - V|^2> = 3T; origin: <|v|^2> = 3 (T + |V|^2/3), the observable at offset 19.
      const double second = std::string(center) == "bulk" ? 3.0 * T : 3.0 * T_total;
      const Integrals radial = integrate(run.record, "histogram", m, d, run.ensembles, 0.0, h);
      ASSERT_EQ(radial.overflow, 0u) << center << " row " << m;
      EXPECT_NEAR(radial.m0, 1.0, 1e-12);
      EXPECT_NEAR(radial.m2, second, h * std::sqrt(second) + h * h / 4) << center << " row " << m;
      largest_shift = std::max(largest_shift, 3.0 * (T_total - T));

      // The component histogram is about V whatever the center: bins of width 2R/K on [-R, R).
      const Integrals x = integrate(run.record, "histogram_component", m, d, run.ensembles,
                                    -d.histogram.radius, 2.0 * h);
      ASSERT_EQ(x.overflow, 0u);
      EXPECT_NEAR(x.m0, 1.0, 1e-12);
      EXPECT_NEAR(x.m1, 0.0, h);  // sum_j (v_j - V)_x = 0 in each ensemble
      EXPECT_NEAR(x.m2, Pxx, 2.0 * h * std::sqrt(Pxx) + h * h) << "row " << m;
    }
    // The bulk velocity does wander, so that the two centers are told apart above: 3 times the
    // binning bound is 0.13 E|V|^2 at t = 10, where chi-square(12) falls with probability 1e-4.
    EXPECT_GT(largest_shift, 3 * (h * std::sqrt(6.0) + h * h / 4));
  }
}
