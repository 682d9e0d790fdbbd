#pragma once
// The `dsmc:` section of a run config: GRW05 / RW05 parameters.
#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "granboltz/physics/flight/list.hpp"
#include "granboltz/physics/kernel.hpp"
#include "granboltz/physics/restitution/laws.hpp"
#include "granboltz/physics/thermostat/list.hpp"

namespace YAML {
class Emitter;
}

namespace granboltz {

class Section;

enum class Scheme { kNoSplit, kEuler, kStrang };
/// global: U_max = 2 max|v - V| for all pairs (the papers); pairwise: B_ij <=
/// C(|v_i-V|+|v_j-V|)^lambda.
enum class MajorantKind { kGlobal, kPairwise };
/// paper: U_max := max(U_max, |v_i - V|, |v_j - V|) (GRW05 2.7/2.10, RW05 eq. 21), the
/// truncated kernel of RW05 eq. (19); strict: U_max := max(U_max, 2|v_i - V|, 2|v_j - V|).
enum class MajorantUpdate { kPaper, kStrict };

/// dsmc.geometry: uniform draws GRW05's direction e uniformly on S^{d-1} (eq. 4); impact draws the
/// impact normal with density proportional to (u^.n)+, the hard-sphere / hard-disk law. In d = 3
/// they are the same law (physics/geometry.hpp); in d = 2 they differ.
enum class Geometry { kUniform, kImpact };

/// The most speed moments dsmc.moments may ask for: <|v - V|^{2p}>, p = 1..16.
inline constexpr int kMaxMoments = 16;

struct HistogramSpec {
  std::uint64_t shells = 0;  ///< K shells of width R/K plus one overflow shell; 0: no histogram
  double radius = 0.0;       ///< R
  /// center: bulk histograms |v - V(t)| with the ensemble's current bulk velocity (white noise
  /// makes V random-walk); origin histograms |v|, GRW05 eq. (37).
  bool bulk = true;
  /// component: also the histogram of (v - V)_x over (-R, R) in K bins plus one for |.| >= R.
  bool component = false;
};

/// dsmc.weights: the stochastic weighted particle method (SWPM, Rjasanow & Wagner 1996/2005).
/// The reduction: merges of a group into two particles that keep its energy (and, kHeatFlux, its
/// central heat flux), or kUnbiased: random weight moves that keep mass, momentum and energy
/// exactly and every other moment in expectation (weighted.hpp, thin_group).
enum class Reduction { kEnergy, kHeatFlux, kUnbiased };
/// dsmc.weights.split: importance splitting along the diffusion path. Every `interval`
/// all particles are kicked to the current time; one beyond `radius` from V heavier than twice
/// its target weight w*(r) = (1/n) (r/radius)^2 exp(-rate (r^power - radius^power)) is split into
/// equal copies, and light ones (below w*/4) play pairwise roulette within a band of w*.
struct SplitSpec {
  bool on = false;
  double radius = 0.0;    ///< r_s: no splitting at |v - V| <= r_s
  double rate = 0.0;      ///< a of the importance function
  double power = 1.0;     ///< b of the importance function
  double interval = 0.0;  ///< time between split sweeps
  double max_radius = std::numeric_limits<double>::infinity();  ///< w* is frozen beyond it
};

struct WeightsSpec {
  bool swpm = false;                ///< false: constant weights 1/n (the papers)
  double kappa = 0.0;               ///< kappa >= 0: pair rate (1 + kappa) max(g_i, g_j) B
  std::uint64_t max_particles = 0;  ///< N_max: a reduction runs when the count exceeds it
  Reduction reduction = Reduction::kUnbiased;
  /// kUnbiased: particles lighter than min_weight times their target weight (1/n, or w*(r) with
  /// split) are thinned away at every reduction.
  double min_weight = 1e-30;
  SplitSpec split;  ///< dsmc.weights.split (absent: off)
};

/// One species of a mixture (dsmc.species). The particles of species a are the block
/// [offset, offset + count) of every ensemble, in the order the species are listed.
struct SpeciesSpec {
  std::string name;
  double fraction = 1.0;  ///< x_a as written; count = N_a from the largest remainder of x_a n
  double mass = 1.0;
  double diameter = 1.0;
  double inertia = 0.0;  ///< kappa_a = 4 I_a/(m_a sigma_a^2) (rough particles)
  std::uint64_t count = 0, offset = 0;
  /// I_a = kappa_a m_a (sigma_a/2)^2.
  double moment_of_inertia() const { return inertia * mass * 0.25 * diameter * diameter; }
};

/// dsmc.roughness: rough particles with tangential restitution beta in [-1, 1] (-1: smooth,
/// 1: perfectly rough) and reduced moment of inertia kappa = 4 I/(m sigma^2) in (0, 2/3].
struct RoughnessSpec {
  bool on = false;
  double beta = -1.0;
  double inertia = 0.4;  ///< kappa of every species unless given per species
  bool inertia_per_species = false;
};

/// The parameter of one section flight (dsmc.drag.gamma, dsmc.shear.rate; physics/flight/): 0 is
/// off. Written as a mapping of species names, per_species holds one value per species (in the
/// order of dsmc.species) and value their largest.
struct FlightParam {
  double value = 0.0;
  std::vector<double> per_species;
  double of(std::size_t species) const {
    return per_species.empty() ? value : per_species[species];
  }
};

/// dsmc.correlations.<name>: one time correlation sampled between the observation rows by a
/// multiple-tau correlator (stats/correlator.hpp; dsmc/observers/correlations.hpp). Every value is
/// resolved when the config is read (the defaults written out), so the stored config says it all.
struct CorrelationSpec {
  bool on = false;
  double every = 0.0;  ///< the sampling interval
  double from = 0.0;   ///< the first sample's time (default dsmc.steady_from, else 0)
  unsigned points = 16, averaging = 2, levels = 0;  ///< the correlator's resolution
  std::uint64_t particles = 0;  ///< velocity: the tagged particles of each species (the first ones)
  /// The samples from `from` to t_end: time(k), k = 0..samples-1.
  std::uint64_t samples = 0;
  /// The time of sample k: from + k every (t_end where rounding would pass it).
  double time(std::uint64_t k, double t_end) const {
    const double t = from + static_cast<double>(k) * every;
    return t < t_end ? t : t_end;
  }
};
/// dsmc.correlations: the velocity autocorrelation of tagged particles (self-diffusion), the
/// shear stress (and the normal-stress differences), the heat flux.
struct CorrelationsSpec {
  CorrelationSpec velocity, stress, heat_flux;
  bool any() const { return velocity.on || stress.on || heat_flux.on; }
  /// The first sample time of any of them after `after` (+infinity: none): where a run stops
  /// its ensembles besides the rows (a replay of the run must stop there too).
  double next_after(double after, double t_end) const;
};

/// The most species dsmc.species may list.
inline constexpr std::size_t kMaxSpecies = 16;

struct SourceRun;

struct DsmcConfig {
  std::uint64_t particles = 0;             ///< n
  int dimension = 3;                       ///< d: velocities in R^d (2: z = 0)
  Geometry geometry = Geometry::kUniform;  ///< default impact in d = 2, uniform in d = 3
  Scheme scheme = Scheme::kNoSplit;
  std::uint64_t steps = 0;  ///< K: time steps of the splitting schemes, dt = t_end / K
  double alpha = 1.0;       ///< restitution coefficient, 0 < alpha <= 1 (the constant law)
  /// dsmc.restitution: the law eps(g_n). ConstantRestitution{alpha} unless another law is given
  /// (then alpha is 1 and unused).
  RestitutionLaw restitution;
  double beta = 0.0;  ///< heating strength (white noise), >= 0; the largest if per species
  std::vector<double> beta_species;  ///< dsmc.beta as a mapping of species names (else empty)
  /// dsmc.drag, dsmc.shear: the section flights' parameters, in flight::SectionFlights order.
  std::array<FlightParam, flight::SectionFlights::kCount> flights{};
  std::array<bool, flight::SectionFlights::kCount> flight_written{};  ///< the section was given
  Thermostat thermostat = Thermostat::kWhiteNoise;
  VhsKernel kernel;                  ///< lambda, C, and gamma (the prefactor of the collision term)
  double initial_temperature = 1.0;  ///< T0; with a tensor its trace / d
  /// dsmc.initial.temperature written as a d x d matrix: the temperature tensor of an anisotropic
  /// Maxwellian (row-major, symmetric, positive definite); empty: isotropic at T0.
  std::vector<double> initial_temperature_tensor;
  /// dsmc.initial.heat_flux: d numbers, the heat flux q = (m/2) <c |c|^2> of a skewed start
  /// (dsmc/initial_state.hpp, SkewedState); empty: none.
  std::vector<double> initial_heat_flux;
  double t_end = 0.0;
  double observe_every = 0.0;  ///< observations at m * observe_every, m = 0..t_end/observe_every
  /// dsmc.observe, given in place of observe_every (which is then 0, so that the steady window
  /// t > steady_from + 1e-9 observe_every is t > steady_from): the observation times
  /// t_1 < ... < t_M = t_end after t_0 = 0, from the log grid or the list. Empty: the uniform grid.
  std::vector<double> observe_times;
  double observe_log_from = 0.0;         ///< dsmc.observe.log.from; 0: observe.times was given
  std::uint64_t observe_per_decade = 0;  ///< dsmc.observe.log.per_decade
  HistogramSpec histogram;
  MajorantKind majorant = MajorantKind::kGlobal;  ///< the majorant used (auto resolved)
  bool majorant_auto = false;  ///< dsmc.majorant: auto (the default) chose `majorant`
  MajorantUpdate majorant_update = MajorantUpdate::kStrict;
  int moments = 4;      ///< P: observe <|v - V|^{2p}> for p = 1..P (0 <= P <= kMaxMoments)
  bool steady = false;  ///< time averages over the observations with t > steady_from
  double steady_from = 0.0;
  /// dsmc.steady_ci: batch (the default) gives /steady intervals from independent ensembles or
  /// within-ensemble blocking; independent treats every (ensemble, t_m) sample as independent,
  /// which is what the reproduction profiles ask for (their outputs keep their bits).
  bool steady_ci_independent = false;
  WeightsSpec weights;            ///< dsmc.weights (absent: constant weights)
  CorrelationsSpec correlations;  ///< dsmc.correlations (absent: none)
  /// dsmc.species (empty: one species of unit mass and diameter, the papers' gas). Filled for
  /// every general run (see general()), with one unnamed species if none was written.
  std::vector<SpeciesSpec> species;
  bool species_written = false;      ///< dsmc.species was given
  std::vector<double> alpha_matrix;  ///< K x K restitution coefficients when written as a matrix
  RoughnessSpec roughness;
  double initial_rotational_temperature = 1.0;  ///< T_rot(0) (rough), default the temperature
  bool rotational_temperature_written = false;
  /// dsmc.initial.from: an earlier output whose final state starts every ensemble (ensemble e
  /// takes the source's ensemble e at its t_end, re-simulated from the source's stored config
  /// and seed: dsmc/initial_from.hpp); empty: none. initial_from_hash is the text_hash of the
  /// source's stored config, written into this run's config and checked when it is read again.
  std::string initial_from;
  std::uint64_t initial_from_hash = 0;
  std::shared_ptr<const SourceRun> source;

  /// The general gas engine (dsmc/gas.hpp) runs it: mixtures or rough particles.
  bool general() const { return species_written || roughness.on; }
  double drag_gamma() const { return flights[0].value; }
  double shear_rate() const { return flights[1].value; }
  /// Drag or shear between the collisions (beyond the papers' white noise).
  bool linear_flight() const { return drag_gamma() != 0.0 || shear_rate() != 0.0; }
  /// The free flight of species a (0 for one species).
  LinearFlight flight_of(std::size_t a) const {
    return {beta_species.empty() ? beta : beta_species[a], flights[0].of(a), flights[1].of(a)};
  }
  /// alpha of the pair of species (a, b).
  double pair_alpha(std::size_t a, std::size_t b) const {
    return alpha_matrix.empty() ? alpha : alpha_matrix[a * species.size() + b];
  }

  std::uint64_t observations() const;  ///< M: observation times are t_m, m = 0..M
  double time_step() const { return t_end / static_cast<double>(steps); }
};

/// The run named by dsmc.initial.from, as its output's stored config describes it.
struct SourceRun {
  std::uint64_t seed = 0;
  std::uint64_t ensembles = 0;
  DsmcConfig dsmc;
};

DsmcConfig read_dsmc(const Section& s);
void emit_dsmc(YAML::Emitter& out, const DsmcConfig& c);
/// dsmc.correlations (dsmc/config_correlations.cpp): read, with the rest of c already read, and
/// written back resolved.
void read_correlations(const Section& s, DsmcConfig& c);
void emit_correlations(YAML::Emitter& out, const DsmcConfig& c);
const char* scheme_name(Scheme s);
const char* reduction_name(Reduction r);
const char* majorant_name(MajorantKind m);
const char* geometry_name(Geometry g);

/// dsmc.majorant: auto picks pairwise up to this many particles (where the pairwise majorant is
/// exact and faster; measured in `make bench`), global beyond.
inline constexpr std::uint64_t kAutoPairwiseMaxParticles = 2'000'000;
/// The majorant `auto` chooses for a config (everything but `majorant` already read).
MajorantKind auto_majorant(const DsmcConfig& c);

}  // namespace granboltz
