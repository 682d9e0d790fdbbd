"""Free cooling (Haff's law) and the homogeneous cooling state (HCS) with the Gaussian thermostat,
beside the white-noise steady state: the temperature law and the references for a2 (van
Noije-Ernst, the exact Maxwell-molecule value).  Their table rows and verdicts:
granboltz.reproduction.beyond.

Units: density 1, kernel B = C |u|^lambda, collision term gamma Q (docs/config.md, Thermostats).
Sonine coefficient a2 = <c^4>/15 - 1 of the velocities scaled to T = 1, read from a run as the
steady average of `fourth_moment` (M4 - 15 T^2 per sample) over 15 <T>^2.
"""

import math

import numpy as np

from .dimension import check_dimension
from .maxwell_hierarchy import hcs_a2, hcs_scaled_moments, steady_a2_formula
from .sonine import cooling_rate, first_sonine_a2


# ----------------------------------------------------------------------------- theory
def vne_hcs_a2(alpha, d=3, geometry=None):
    """First-Sonine a2 of the hard-sphere HCS (van Noije & Ernst 1998, d = 3):
    16(1 - alpha)(1 - 2 alpha^2)/(81 - 17 alpha + 30 alpha^2 (1 - alpha)); hard disks in d = 2."""
    return first_sonine_a2(alpha, "gaussian", 1, d, geometry)


def vne_heated_a2(alpha, d=3, geometry=None):
    """First-Sonine a2 of the white-noise steady state of hard spheres (van Noije & Ernst 1998):
    16(1 - alpha)(1 - 2 alpha^2)/(241 - 177 alpha + 30 alpha^2 (1 - alpha)); hard disks in d = 2."""
    return first_sonine_a2(alpha, "white_noise", 1, d, geometry)


def theory_a2(thermostat, kernel_lambda, alpha, d=3, geometry=None):
    """(value, name) of the reference a2: exact for Maxwell molecules (lambda = 0, d = 3; HCS from
    the moment hierarchy, steady white noise in closed form), first Sonine for hard spheres (and
    hard disks, d = 2)."""
    d = check_dimension(d, (2, 3), "theory_a2")
    if kernel_lambda == 0:
        check_dimension(d, (3,), "theory_a2 (Maxwell molecules)")
        if thermostat == "gaussian":
            try:  # the HCS of Maxwell molecules has a power-law tail: <c^8> is infinite for alpha <= 0.4
                hcs_scaled_moments(4, alpha)
            except ValueError:
                return float(hcs_a2(alpha)), "exact (moment hierarchy); <c^8> infinite: CI not valid"
            return float(hcs_a2(alpha)), "exact (moment hierarchy)"
        return float(steady_a2_formula(alpha)), "exact (moment hierarchy)"
    if thermostat == "gaussian":
        return vne_hcs_a2(alpha, d, geometry), "van Noije-Ernst, first Sonine"
    return vne_heated_a2(alpha, d, geometry), "van Noije-Ernst, first Sonine"


def haff_temperature(t, T0, alpha, gamma, C, kernel_lambda, n=None, d=3, geometry=None):
    """Expected centred temperature of free cooling: Maxwell molecules T0 e^{-gamma pi C (1 -
    alpha^2) t} (GRW05 eq. 16, beta = 0; exact), hard spheres Haff's law T0/(1 + t/t0)^2 with
    t0 = 2/(K sqrt(T0)), K = (16/3) sqrt(pi) gamma C (1 - alpha^2)(1 + 3 a2/16), a2 of the HCS
    in first Sonine.  With n, T0 -> T0 (1 - 1/n): the centred estimator's bias (exact for Maxwell).
    d = 2: the rates of granboltz.theory.sonine.cooling_rate (hard disks: impact geometry)."""
    t = np.asarray(t, dtype=float)
    T0 = T0 * (1 - 1 / n) if n else T0
    if kernel_lambda == 0:
        return T0 * np.exp(-cooling_rate(1.0, alpha, gamma, C, 0, d=d, geometry=geometry) * t)
    K = cooling_rate(1.0, alpha, gamma, C, 1, a2=vne_hcs_a2(alpha, d, geometry), d=d, geometry=geometry)
    return T0 / (1 + t * K * math.sqrt(T0) / 2) ** 2
