"""Beyond the papers: the Sonine coefficients a2, a3 of hard disks (d = 2, impact normals) in the
homogeneous cooling state (Gaussian thermostat) and the white-noise steady state, against van
Noije-Ernst's d = 2 first Sonine a2 and the second Sonine approximation (granboltz.theory.sonine); the
white-noise steady temperature against the energy balance: the references (the rows, judgement
and verdicts of the report item are granboltz.reproduction.disks).

Units: density 1, kernel B = C |u| per unit angle (docs/config.md, Dimension and collision
geometry), collision term gamma Q.  a2, a3, T are the simulator's steady averages (/steady/a2,
a3, temperature), with intervals from the ensembles' time averages.
"""

import math

import numpy as np

from .dimension import check_dimension, check_geometry
from .sonine import first_sonine_a2, second_sonine


def _disks(what, d, geometry):
    """d = 2 with the hard-disk law: the only (d, geometry) of these references."""
    check_geometry(check_dimension(d, (2,), what), geometry, what)


def disk_references(thermostat, alpha, d=2, geometry=None):
    """(van Noije-Ernst a2, second-Sonine a2, second-Sonine a3) of hard disks, d = 2, impact
    geometry [approx; the second Sonine derived, granboltz.theory.sonine.second_sonine]."""
    _disks("disk_references", d, geometry)
    a2_2, a3_2 = second_sonine(alpha, thermostat, d=2, geometry=geometry)
    return float(first_sonine_a2(alpha, thermostat, 1, d=2, geometry=geometry)), float(a2_2), float(a3_2)


def disk_steady_temperature(alpha, beta, gamma, C, a2=0.0, a3=0.0, n=None, d=2, geometry=None):
    """White-noise steady temperature of hard disks (d = 2, C per unit angle): 2 beta = K T^(3/2),
    K = pi^(3/2) gamma C (1 - alpha^2)(1 + 3 a2/16 + a3/64) [approx: the Sonine factor of
    E|u|^3]; with n, E[T] = (1 - 1/n)(2 beta/K)^(2/3), the n-particle energy balance
    (tests/test_dimension.cpp: it fixes the pairs' mean |u|^3, and their mean |u|^2 is
    2d E[T] n/(n - 1)).  d = 2 with the impact geometry only."""
    _disks("disk_steady_temperature", d, geometry)
    K = math.pi**1.5 * gamma * C * (1 - np.asarray(alpha, float) ** 2) * (1 + 3 * np.asarray(a2, float) / 16
                                                                         + np.asarray(a3, float) / 64)
    return (1 - 1 / n if n else 1.0) * (2 * beta / K) ** (2 / 3)
