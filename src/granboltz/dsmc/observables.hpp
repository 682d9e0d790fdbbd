#pragma once
// Observers of one particle system at one time: the moments of GRW05 eqs. (9)-(13) and RW05
// eq. (29), and the radial histogram of GRW05 eq. (37). Pure functions of the particles.
#include <array>
#include <cstdint>
#include <span>
#include <string>

#include "granboltz/dsmc/config.hpp"
#include "granboltz/dsmc/particles.hpp"

namespace granboltz {

/// The observables, flattened into one array of scalars. Offsets and shapes in kObservables.
inline constexpr int kNumScalars = 20;
using Observation = std::array<double, kNumScalars>;

struct ObservableInfo {
  const char* name;  ///< HDF5 group name
  int offset;        ///< first scalar in an Observation
  int rank;          ///< 0 scalar, 1 vector [3], 2 tensor [3, 3]
  const char* description;
};

inline constexpr ObservableInfo kObservables[] = {
    {"density", 0, 0, "number density rho (particle weights 1/n: always 1)"},
    {"bulk_velocity", 1, 1, "V = m / rho (GRW05 eq. 12)"},
    {"temperature", 4, 0, "T = (tr M - rho |V|^2) / (d rho) (GRW05 eq. 13 in d dimensions)"},
    {"pressure_tensor", 5, 2, "P = int (v-V)(v-V)^T f dv"},
    {"heat_flux", 14, 1, "q = 1/2 int (v-V) |v-V|^2 f dv"},
    {"fourth_moment", 17, 0, "gamma = int |v-V|^4 f dv - d(d+2) T^2 (RW05 §4.1; 15 T^2 in d = 3)"},
    {"crit", 18, 0, "deviation from the Maxwellian, Crit (RW05 eq. 29)"},
    {"temperature_uncentred", 19, 0,
     "(1/d) int |v|^2 f dv = T + |V|^2/d: the estimator phi(v) = |v|^2/3 of RW05 §4.1, "
     "behind the published error tables"},
};

inline int observable_size(const ObservableInfo& o) {
  return o.rank == 0 ? 1 : o.rank == 1 ? 3 : 9;
}

/// A speed moment may not exceed this, so that its square and the sum of squares over up to
/// 10^8 ensembles stay finite doubles (the exact sums hold any finite double).
inline constexpr double kMomentLimit = 1e150;
/// "moment_<2p>": the dataset name of <|v - V|^{2p}>.
std::string moment_name(int p);

/// All moments of the empirical measure (1/n) sum delta_{v_j}, computed in two passes about the
/// bulk velocity, for velocities in R^d (d = 2: v_z = 0, and the z rows of P, q are 0). If
/// `moments` is not empty (at most kMaxMoments entries), moments[p - 1] receives the speed moment
/// <|v - V|^{2p}> = (1/n) sum_j |v_j - V|^{2p}, p = 1..moments.size(), summed in the second pass;
/// the other observables do not depend on it.
Observation measure(std::span<const Particle> particles, std::span<double> moments = {},
                    int dimension = 3);

/// measure() about a given centre V instead of the particles' mean (which measure() passes).
Observation measure_about(std::span<const Particle> particles, Vec3 V, std::span<double> moments,
                          int dimension);

/// Crit(t) of RW05 eq. (29) from the central moments. In d dimensions each term is normalised by
/// its Maxwellian variance as in d = 3: 1/2 |P - p I|^2/T^2 + 2/(d+2) |q|^2/T^3 +
/// gamma^2/(8 d (d+2) T^4) (p = tr P/d; d = 3 gives 2/5 and 1/120).
double crit(double temperature, const double* pressure, const double* heat_flux,
            double fourth_moment, int dimension = 3);

/// Adds the radial histogram counts of r_j = |v_j - c| to counts[0..K]: shell k < K holds
/// k h <= r < (k+1) h, h = R/K (GRW05 eq. 37), shell K holds r >= R. The center c is the bulk
/// velocity V for spec.bulk, else the origin (then c is not used).
void radial_histogram(std::span<const Particle> particles, const HistogramSpec& spec, Vec3 V,
                      std::uint64_t* counts);

/// The bin of x = (v - V)_x in the component histogram: k < K for -R + k w <= x < -R + (k+1) w,
/// w = 2R/K and |x| < R; K for |x| >= R (and a NaN).
std::uint64_t component_bin(double x, const HistogramSpec& spec);

/// Adds the counts of (v_j - V)_x to counts[0..K] (component_bin).
void component_histogram(std::span<const Particle> particles, const HistogramSpec& spec, Vec3 V,
                         std::uint64_t* counts);

}  // namespace granboltz
