#pragma once
// The observables of the general gas (dsmc/gas.hpp): the mixture's row, one row per species and
// the rotational temperature, from the velocities (and spins) at one time.
#include <span>
#include <vector>

#include "granboltz/dsmc/config.hpp"
#include "granboltz/dsmc/observables.hpp"
#include "granboltz/dsmc/particles.hpp"

namespace granboltz {

/// Every row is measure_about() of the mass-scaled peculiar velocities c_j = sqrt(m_j)(v_j - V),
/// V the centre-of-mass velocity, about 0: so T = sum_j m_j |v_j - V|^2/(d n) = sum_a x_a T_a and
/// P = (1/n) sum_j m_j (v_j - V)(v_j - V)^T are the mixture's, and a species' row has
/// T_a = m_a <|v - V|^2>_a/d. Heat flux, fourth moment, Crit and the speed moments are those of
/// c (for one mass, of v - V; a2 and a3 do not depend on the mass of a species). The bulk velocity
/// of the mixture's row is V, that of a species' row the species' mean velocity; density is 1 for
/// the mixture and N_a/n for a species; temperature_uncentred is T + (mean mass) |V|^2/d, and
/// m_a <|v|^2>_a/d for a species.
/// `species_rows[k]`, `species_moments[k]` receive the rows of extra_row_sets() (each species,
/// then T_rot = sum_j I_j |omega_j|^2/(n d_rot) when rough) for this observation time.
Observation measure_gas(const DsmcConfig& d, std::span<const Particle> particles,
                        std::span<const Vec3> spins, std::span<double> moments,
                        const std::vector<double*>& species_rows,
                        const std::vector<double*>& species_moments);

}  // namespace granboltz
