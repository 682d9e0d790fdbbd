#pragma once
// Viscoelastic spheres (Schwager & Poschel 1998; Ramirez, Poschel, Brilliantov & Schwager 1999):
//   eps(g_n) = 1 - C1 x + C2 x^2,  x = delta g_n^(1/5),
//   C1 = Gamma(3/5) sqrt(pi) / (2^(1/5) 5^(2/5) Gamma(21/10)),  C2 = (3/5) C1^2.
// The two-term series is an expansion in x; with C2 = (3/5) C1^2 it has its minimum 7/12 at
// x* = 5/(6 C1) = 0.7225 and then rises back towards 1, which is unphysical, so eps is held at
// 7/12 for x >= x* (continuous, non-increasing in g_n).
#include <array>
#include <limits>

#include "granboltz/physics/restitution/param.hpp"
#include "granboltz/physics/restitution/tenth_root.hpp"

namespace granboltz {

struct ViscoelasticRestitution {
  static constexpr const char* kName = "viscoelastic";
  static constexpr bool kScaleFree = false;  // eps depends on the true g_n (Gaussian: s g_n)
  static constexpr double kC1 = 1.1534488580952884;
  static constexpr double kC2 = 0.6 * kC1 * kC1;       // 0.79826656...
  static constexpr double kXHold = 5.0 / (6.0 * kC1);  // the series' minimum, 0.72247...
  static constexpr double kEpsHold = 7.0 / 12.0;       // eps(kXHold)
  double delta = 0.0;

  static constexpr std::array<LawParam<ViscoelasticRestitution>, 1> kParams{{
      {"delta", &ViscoelasticRestitution::delta, 0.0, false,
       std::numeric_limits<double>::infinity(), false, "must be >= 0"},
  }};

  /// eps as a function of x = delta g_n^(1/5), held at 7/12 beyond the minimum.
  static constexpr double eps_of_x(double x) {
    return x >= kXHold ? kEpsHold : 1.0 - x * (kC1 - kC2 * x);
  }
  /// eps from the squared true normal relative speed g_n^2 (g_n^(1/5) = (g_n^2)^(1/10): no sqrt).
  double eps_of_g2(double g2) const { return eps_of_x(delta * tenth_root(g2)); }
};

}  // namespace granboltz
