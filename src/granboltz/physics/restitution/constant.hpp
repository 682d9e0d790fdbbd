#pragma once
// Constant restitution: eps(g_n) = alpha for every normal speed (GRW05, RW05). Its collisions go
// through physics/collision.hpp's collide() unchanged, so existing configs keep their bits.
#include <array>

#include "granboltz/physics/restitution/param.hpp"

namespace granboltz {

struct ConstantRestitution {
  static constexpr const char* kName = "constant";
  static constexpr bool kScaleFree = true;  // eps does not depend on the size of g_n
  double alpha = 1.0;

  static constexpr std::array<LawParam<ConstantRestitution>, 1> kParams{{
      {"alpha", &ConstantRestitution::alpha, 0.0, true, 1.0, false, "must satisfy 0 < alpha <= 1"},
  }};

  /// eps from the squared true normal relative speed g_n^2.
  constexpr double eps_of_g2(double) const { return alpha; }
};

}  // namespace granboltz
