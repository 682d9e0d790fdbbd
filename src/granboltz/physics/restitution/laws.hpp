#pragma once
// The restitution laws (dsmc.restitution). A new law is one header in this folder (its hot
// struct: kName, kScaleFree, kParams, eps_of_g2) and one entry in RestitutionLaws below; the
// config reads, checks and emits it from kParams, the engines apply it through collide_law()
// (collide.hpp).
#include <variant>

#include "granboltz/physics/restitution/constant.hpp"
#include "granboltz/physics/restitution/viscoelastic.hpp"

namespace granboltz {

template <class... Laws>
struct LawList {
  using Variant = std::variant<Laws...>;
  /// Calls f(Law{}) for every law, in order.
  template <class F>
  static void each(F&& f) {
    (f(Laws{}), ...);
  }
};

// The constant law comes first: a default RestitutionLaw is alpha = 1, today's model.
using RestitutionLaws = LawList<ConstantRestitution, ViscoelasticRestitution>;
using RestitutionLaw = RestitutionLaws::Variant;

inline bool is_constant(const RestitutionLaw& law) {
  return std::holds_alternative<ConstantRestitution>(law);
}

}  // namespace granboltz
