#pragma once
// The `intruder:` and `needle:` sections of a run config: TV06 parameters.
#include <cstdint>

namespace YAML {
class Emitter;
}

namespace granboltz {

class Section;

enum class BathKind { kGaussian, kPowerLaw };
enum class IntruderMethod { kGillespie, kDsmc };
/// DSMC intruder: which bath particles are replaced by fresh draws from f (docs/tv06.md).
/// kTested: every particle tested for a collision, accepted or not (exact: the bath stays
/// independent draws from f); kCollided: only the collision partners (biased: slow particles
/// accumulate); kNone: the bath of TV06 §4 as written, drawn once (a finite-n sample of f).
enum class BathRefresh { kTested, kCollided, kNone };
/// Needle: how the waiting time of eq. 23 is drawn. kThinning: candidate times at the rate
/// bound Phi(|v1|, omega), accepted with probability Phi(t)/bound (exact, no root finding);
/// kInversion: TV06's inversion of ∫_0^t Phi = -ln xi (quadrature and a bracketed root finder).
enum class NeedleWaitingTime { kThinning, kInversion };

/// Bath velocity density: gaussian sqrt(a/pi) exp(-a v^2) (T_B = 1/(2a)) or
/// power law sqrt(2a)/pi / (1 + a^2 v^4) (T_B = <v^2> = 1/a).
struct BathSpec {
  BathKind kind = BathKind::kGaussian;
  double a = 1.0;
};

/// A symmetric velocity histogram on [-range, range] with `bins` bins.
struct VelocityHistogramSpec {
  std::uint64_t bins = 0;  ///< 0: no histogram
  double range = 0.0;
};

struct IntruderConfig {
  BathSpec bath;
  double mass = 1.0;     ///< M (bath particle mass 1)
  double alpha = 1.0;    ///< restitution, 0 <= alpha <= 1
  double density = 1.0;  ///< bath number density rho
  std::uint64_t collisions = 0;
  IntruderMethod method = IntruderMethod::kGillespie;
  double sample_every = 0.0;            ///< delta t between samples; 0: the mean free time 1/phi(0)
  std::uint64_t warmup = 0;             ///< collisions discarded before sampling starts
  std::uint64_t bath_particles = 1000;  ///< DSMC method only
  BathRefresh bath_refresh = BathRefresh::kTested;  ///< DSMC method only
  VelocityHistogramSpec histogram;
};

struct NeedleConfig {
  double mass = 1.0;     ///< M
  double length = 1.0;   ///< L (uniform rod, I = M L^2 / 12)
  double alpha = 1.0;    ///< restitution, 0 <= alpha <= 1
  double a = 1.0;        ///< Gaussian bath parameter
  double density = 1.0;  ///< bath number density rho
  std::uint64_t collisions = 0;
  double sample_every = 0.0;
  std::uint64_t warmup = 0;
  NeedleWaitingTime waiting_time = NeedleWaitingTime::kThinning;
  VelocityHistogramSpec velocity_histogram;  ///< of the velocity component v1x
  VelocityHistogramSpec omega_histogram;     ///< of the angular velocity omega
};

IntruderConfig read_intruder(const Section& s);
NeedleConfig read_needle(const Section& s);
void emit_intruder(YAML::Emitter& out, const IntruderConfig& c);
void emit_needle(YAML::Emitter& out, const NeedleConfig& c);

}  // namespace granboltz
