"""The exponential tail of the homogeneous cooling state (HCS) of hard spheres: its amplitude and the
cooling rates it takes (the fits of runs measured deep with weighted particles, and their verdict,
are granboltz.reproduction.hcs_tail).

Theory (van Noije & Ernst 1998; /work/shared/reference/beyond.md §3): in scaled velocities a fast
particle is pushed outward by the thermostat's drift (zeta/2) v and lost at the rate
nu(v) = 4 pi gamma C v (d = 3, density 1), so (zeta/2) v f' = -4 pi gamma C v f and

    f ~ exp(-A c),  c = |v - V|/v0,  v0 = sqrt(2 T/m),  A = 8 pi gamma C v0 / zeta,

with zeta = -d ln T/dt the cooling rate of the same run (its /steady/cooling_rate, docs/output.md):
no Sonine input.
"""

import math

from .dimension import check_dimension, check_geometry
from .sonine import first_sonine_a2


def thermal_speed(T, m=1.0):
    """v0 = sqrt(2 T/m)."""
    return math.sqrt(2.0 * T / m)


def hcs_amplitude(zeta, gamma, C, T, m=1.0, d=3):
    """A = 8 pi gamma C v0/zeta (d = 3; 4 pi gamma C v0/zeta for hard disks, d = 2, beyond.md §3)."""
    k = 8.0 * math.pi if check_dimension(d, (2, 3), "hcs_amplitude") == 3 else 4.0 * math.pi
    return k * gamma * C * thermal_speed(T, m) / zeta


def maxwellian_cooling_rate(alpha, gamma, C, T, m=1.0, d=3, geometry=None):
    """zeta of hard spheres with a Maxwellian f: 8 pi gamma C v0 (1 - alpha^2)/(3 sqrt(pi/2))
    (the A = 3 sqrt(pi/2)/(1 - alpha^2) of beyond.md §3); hard disks (d = 2, impact): pi^(3/2)
    gamma C (1 - alpha^2) v0/sqrt(2) (granboltz.theory.sonine.cooling_rate)."""
    if check_dimension(d, (2, 3), "maxwellian_cooling_rate") == 2:
        check_geometry(d, geometry, "maxwellian_cooling_rate")
        return math.pi**1.5 * gamma * C * (1.0 - alpha**2) * thermal_speed(T, m) / math.sqrt(2.0)
    return 8.0 * math.pi * gamma * C * thermal_speed(T, m) * (1.0 - alpha**2) / (3.0 * math.sqrt(math.pi / 2.0))


def sonine_cooling_rate(alpha, gamma, C, T, m=1.0, d=3, geometry=None):
    """First-Sonine HCS cooling rate of hard spheres, d = 3: the Maxwellian one times
    (1 + 3 a2/16), a2 = 16 (1 - alpha)(1 - 2 alpha^2)/(81 - 17 alpha + 30 alpha^2 (1 - alpha))
    (van Noije & Ernst 1998); hard disks (d = 2) with their first-Sonine a2."""
    if check_dimension(d, (2, 3), "sonine_cooling_rate") == 2:
        a2 = float(first_sonine_a2(alpha, "gaussian", 1, 2, geometry))
        return maxwellian_cooling_rate(alpha, gamma, C, T, m, 2, geometry) * (1.0 + 3.0 * a2 / 16.0)
    a2 = 16.0 * (1.0 - alpha) * (1.0 - 2.0 * alpha**2) / (81.0 - 17.0 * alpha + 30.0 * alpha**2 * (1.0 - alpha))
    return maxwellian_cooling_rate(alpha, gamma, C, T, m) * (1.0 + 3.0 * a2 / 16.0)
