#pragma once
// White-noise heating beta Delta_v f (GRW05 eq. 1): every velocity performs Brownian motion,
// v(t + s) = v(t) + sqrt(2 beta s) xi (eq. 23). The engines kick a particle from its own last time
// to the time it is next used (both partners of an event, GRW05 step 2.5; everyone at the
// observations and at the splitting steps), which is exact for any s.
#include "granboltz/core/hot.hpp"
#include "granboltz/core/vec3.hpp"
#include "granboltz/physics/heating.hpp"
#include "granboltz/physics/thermostat/kind.hpp"

namespace granboltz {

struct WhiteNoiseThermostat {
  static constexpr Thermostat kId = Thermostat::kWhiteNoise;
  static constexpr const char* kName = "white_noise";
  static constexpr bool kKicks = true;
  static constexpr bool kLazyScale = false;
  double beta = 0.0;

  /// Kicks the partners a and b over the times sa and sb since their last kicks, in R^D.
  template <int D, class E>
  GRANBOLTZ_HOT void kick_pair(Vec3& a, double sa, Vec3& b, double sb, E& eng) const {
    white_noise_kick2<D>(a, sa, b, sb, beta, eng);
  }
};

}  // namespace granboltz
