"""Sonine coefficients a2, a3 and the steady temperature of the heated homogeneous gas, for the
project's kernel B = C |u|^lambda (lambda = 1 hard spheres, 0 Maxwell molecules).

Conventions as the simulator's: density 1, collision term gamma Q, white-noise heating beta
(dT/dt = 2 beta from the kicks), T = <|v - V|^2>/d, c = (v - V)/sqrt(2T), and the Sonine expansion
f = f_M (1 + a2 S2(c^2) + a3 S3(c^2)), so a2 = d/(d+2) <v^4>/<v^2>^2 - 1 (reference/beyond.md).
Labels in the docstrings: [exact] a result of the Boltzmann equation, [approx] a Sonine or
Maxwellian approximation (a few per cent is the best to expect).  Thermostat names are the
config's: "white_noise", and "gaussian" (or "hcs") for the homogeneous cooling state, whose
scaled state the Gaussian thermostat gives exactly.
"""

import math
from fractions import Fraction
from functools import lru_cache

import numpy as np

from . import maxwell_hierarchy as mh
from .dimension import check_dimension, check_geometry


def _is_hcs(thermostat):
    if thermostat in ("gaussian", "hcs"):
        return True
    if thermostat == "white_noise":
        return False
    raise ValueError(f"thermostat must be 'white_noise', 'gaussian' or 'hcs', not {thermostat!r}")


# ----------------------------------------------------------------------------- a2, a3
def first_sonine_a2(alpha, thermostat="white_noise", kernel_lambda=1, d=3, geometry=None):
    """First-Sonine a2 (linear in a2, van Noije & Ernst 1998, Granular Matter 1, 57) [approx;
    exact for lambda = 0, where the hierarchy closes].  d = 3: any lambda (beyond.md §2, which
    gives vNE's d = 3 line at lambda = 1); d = 2: hard disks only (lambda = 1, geometry impact;
    beyond.md §1)."""
    d = check_dimension(d, (2, 3), "first_sonine_a2")
    a, lam, hcs = np.asarray(alpha, dtype=float), float(kernel_lambda), _is_hcs(thermostat)
    if d == 2:
        check_geometry(d, geometry, "first_sonine_a2")
    if d == 3:
        num = 16 * (1 - a) * (5 - 2 * lam - (lam + 5) * a**2)
        cubic = 2 * lam**3 + 7 * lam**2
        den = ((cubic + 194 * lam + (40 if hcs else 520)) - a * (cubic + 162 * lam + (-120 if hcs else 360))
               + (lam + 2) * (lam + 4) * (lam + 5) * a**2 * (1 - a))
    elif d == 2 and lam == 1:
        num = 16 * (1 - a) * (1 - 2 * a**2)
        den = (9 + 24 * d - a * (41 - 8 * d) if hcs else 73 + 56 * d - 3 * a * (35 + 8 * d)) + 30 * a**2 * (1 - a)
    else:
        raise ValueError(f"first_sonine_a2: d = 3 (any lambda) or d = 2 with lambda = 1, not d = {d}, lambda = {lam}")
    return num / den


def second_sonine(alpha, thermostat="white_noise", d=3, geometry=None):
    """(a2, a3) of hard spheres (d = 3) or hard disks (d = 2) in the second Sonine approximation
    (a2 and a3 kept, their products dropped) [approx, derived].  d = 3: beyond.md §1.  d = 2: not
    in beyond.md; derived here with tests/sonine_moments.py (exact symbolic Gaussian moments of the
    collision integrals with the hard-disk impact law, the script that reproduces every d = 3
    entry of beyond.md §1-2 and its d = 2 first Sonine) and typed in from its output; e.g. white
    noise alpha = 0.5: (0.034524, -0.005496), HCS alpha = 0.8: (-0.025507, -0.010357).  Where it
    and first_sonine_a2 disagree (HCS at alpha <~ 0.5, where a3 is as large as a2) neither is to
    be trusted."""
    a = np.asarray(alpha, dtype=float)
    d = check_dimension(d, (2, 3), "second_sonine")
    check_geometry(d, geometry, "second_sonine")
    hcs = _is_hcs(thermostat)
    if d == 3 and hcs:
        den = np.polyval([2800, -5600, 34800, -84480, -4410, 25716, 112155, -172458, 214357], a)
        p2 = np.polyval([240, -240, 3072, -4352, -842, -1206, -311, 1623], a)
        p3 = np.polyval([80, -80, 736, -864, -710, 838, 169, -217], a)
    elif d == 3:
        den = np.polyval([2800, -5600, 57200, -129280, 445190, -951564, 1474475, -2278218, 1507877], a)
        p2 = np.polyval([240, -240, 3072, -4352, 8118, -10166, -4791, 6103], a)
        p3 = np.polyval([80, -80, 416, -544, -230, 358, 49, -97], a)
    elif hcs:
        den = np.polyval([2800, -5600, 34800, -74240, 15950, 9060, 70017, -128358, 102195], a)
        p2 = np.polyval([240, -240, 2880, -3520, -738, -30, -321, 849], a)
        p3 = np.polyval([80, -80, 640, -704, -638, 702, 159, -183], a)
    else:
        den = np.polyval([2800, -5600, 52720, -110080, 344910, -662172, 919233, -1266150, 750963], a)
        p2 = np.polyval([240, -240, 2880, -3520, 5406, -6174, -3393, 3921], a)
        p3 = np.polyval([80, -80, 384, -448, -254, 318, 63, -87], a)
    return 16 * (1 - a) * p2 / den, 128 * (1 - a) * p3 / den


def maxwell_a2(alpha, thermostat="white_noise", d=3):
    """a2 of Maxwell molecules (lambda = 0, d = 3) [exact: the moment hierarchy closes]:
    HCS 2(1-alpha)^2/(1 + 2alpha - alpha^2), white noise 2(1-alpha)^2(1+alpha)/(13 - 9alpha +
    alpha^2 - alpha^3) (beyond.md §2; granboltz.theory.maxwell_hierarchy gives the same).  The HCS value
    exists at every alpha, but the variance of its estimator is finite only above
    hcs_moment_threshold(4) = 0.4823 (<c^8> diverges below): no interval for a2 there.  d = 3
    only (the hierarchy of granboltz.theory.maxwell_hierarchy)."""
    check_dimension(d, (3,), "maxwell_a2")
    a = np.asarray(alpha, dtype=float)
    if _is_hcs(thermostat):
        return 2 * (1 - a) ** 2 / (1 + 2 * a - a**2)
    return 2 * (1 - a) ** 2 * (1 + a) / (13 - 9 * a + a**2 - a**3)


def maxwell_a3(alpha, thermostat="white_noise", d=3):
    """a3 of Maxwell molecules (lambda = 0, d = 3) [exact] (beyond.md §2).  HCS:
    8(1-a)^3(16 - 14a + a^2 - a^3)/[(1 + 2a - a^2)(11 - 46a + 20a^2 - 2a^3 + a^4)], NaN at
    alpha <= hcs_moment_threshold(3) = 0.270111 (the pole: <c^6> is infinite there, a power-law
    tail); its estimator has a finite variance only above hcs_moment_threshold(6) = 0.6647.
    White noise (exponential tails, every moment finite): -8(1-a)^3(1+a)^2(10 - 8a + a^2 - a^3)
    / [(13 - 9a + a^2 - a^3)(85 - 61a + 26a^2 - 18a^3 + a^4 - a^5)].  d = 3 only."""
    check_dimension(d, (3,), "maxwell_a3")
    a = np.asarray(alpha, dtype=float)
    if _is_hcs(thermostat):
        value = 8 * (1 - a) ** 3 * (16 - 14 * a + a**2 - a**3) / (
            (1 + 2 * a - a**2) * (11 - 46 * a + 20 * a**2 - 2 * a**3 + a**4))
        return np.where(a > hcs_moment_threshold(3, d), value, np.nan)[()]  # a scalar for a scalar
    return -8 * (1 - a) ** 3 * (1 + a) ** 2 * (10 - 8 * a + a**2 - a**3) / (
        (13 - 9 * a + a**2 - a**3) * (85 - 61 * a + 26 * a**2 - 18 * a**3 + a**4 - a**5))


@lru_cache(maxsize=None)
def hcs_moment_threshold(p, d=3):
    """The alpha below which <c^2p> of the Maxwell-molecule HCS is infinite [exact, to 1e-12]:
    the root of r_p = p r_1 in the closed moment equations (granboltz.theory.maxwell_hierarchy; below
    it the scaled moment grows without bound).  0.270111 (p = 3), 0.4823 (4), 0.5940 (5),
    0.6647 (6); 0.0 when the moment is finite at every alpha (p <= 2).  An interval for a2 needs
    <c^8> finite (p = 4), one for a3 needs <c^12> (p = 6).  d = 3 only."""
    check_dimension(d, (3,), "hcs_moment_threshold")

    def gap(alpha):
        c1, cp = mh.collision_coefficients(1, alpha), mh.collision_coefficients(p, alpha)
        return (1 - cp[0] - cp[-1]) - p * (1 - c1[0] - c1[-1])

    lo, hi = Fraction(0), Fraction(1)
    if gap(lo) > 0:
        return 0.0
    while hi - lo > Fraction(1, 2**42):  # bisection: gap < 0 at lo, >= 0 at hi
        mid = Fraction(round((lo + hi) / 2 * 2**44), 2**44)
        lo, hi = (mid, hi) if gap(mid) < 0 else (lo, mid)
    return float((lo + hi) / 2)


def sonine_from_moments(M2, M4, M6=None, d=3):
    """(a2, a3) from the speed moments M_2p = <|v - V|^2p> [exact identities, beyond.md]:
    a2 = d/(d+2) M4/M2^2 - 1, a3 = 1 + 3 a2 - d^2/((d+2)(d+4)) M6/M2^3 (None without M6); d = 2 or 3,
    the simulator's."""
    d = check_dimension(d, (2, 3), "sonine_from_moments")
    a2 = d / (d + 2) * np.asarray(M4) / np.asarray(M2) ** 2 - 1
    if M6 is None:
        return a2, None
    return a2, 1 + 3 * a2 - d**2 / ((d + 2) * (d + 4)) * np.asarray(M6) / np.asarray(M2) ** 3


# ----------------------------------------------------------------------------- temperature
def cooling_rate(T, alpha, gamma, C, kernel_lambda, a2=0.0, n=None, d=3, geometry=None):
    """zeta(T) of dT/dt = 2 beta - zeta T (the simulator's estimate, app/estimate.cpp): with the
    pair's loss (1 - alpha^2) (u.n)^2/4 at the rate gamma C |S^(d-1)| |u|^lambda per particle,
    zeta T = gamma C |S^(d-1)|/(4 d) (1 - alpha^2) q E|u|^(2+lambda), u = v - w with variance 2T
    per component, q = <(u.n)^2>/|u|^2 over the impact normals: 1/2 in d = 3 (either geometry),
    2/3 for disk impacts and 1/2 for the uniform law in d = 2.  d = 3: zeta = pi gamma C (1 -
    alpha^2) 4^(lambda/2) Gamma((5+lambda)/2)/Gamma(5/2) T^(lambda/2) (16/3 sqrt(pi) gamma C (1 -
    alpha^2) sqrt(T) for hard spheres); d = 2: (pi/4) q gamma C (1 - alpha^2) 4^(1+lambda/2)
    Gamma(2+lambda/2) T^(lambda/2) (pi^(3/2) gamma C (1 - alpha^2) sqrt(T) for hard disks;
    (2 pi/3) and (pi/2) gamma C (1 - alpha^2) for lambda = 0) [exact for lambda = 0, GRW05 eq. 16
    in d = 3; Maxwellian approx otherwise].  a2 multiplies it by 1 + lambda(lambda+2) a2/16 (first
    Sonine: E|u|^p gains p(p-2)/16 a2 in any d; 3/16 for hard spheres, van Noije-Ernst).  With n,
    the factor (n-1)/n of an n-particle system's collision rate."""
    d = check_dimension(d, (2, 3), "cooling_rate")
    geometry = check_geometry(d, geometry, "cooling_rate", ("impact", "uniform"))
    lam = float(kernel_lambda)
    if d == 3:  # (the expression of earlier versions, term for term: the same bits)
        E = 4 ** (lam / 2) * math.gamma((5 + lam) / 2) / math.gamma(2.5)
        prefactor = math.pi
    else:
        E = 4 ** (1 + lam / 2) * math.gamma(2 + lam / 2)
        prefactor = math.pi / 4 * (2 / 3 if geometry == "impact" else 1 / 2)
    finite = 1.0 if n is None else (n - 1) / n
    return (prefactor * gamma * C * (1 - np.asarray(alpha, float) ** 2) * E * np.asarray(T, float) ** (lam / 2)
            * (1 + lam * (lam + 2) * np.asarray(a2, float) / 16) * finite)


def steady_temperature(alpha, beta, gamma, C, kernel_lambda, a2=0.0, n=None, d=3, geometry=None):
    """The white-noise steady temperature from 2 beta = zeta(T) T (cooling_rate):
    T = (2 beta / zeta(1))^(1/(1 + lambda/2)) [exact for lambda = 0; approx otherwise, Maxwellian
    with a2 = 0, first Sonine with the steady a2]."""
    lam = float(kernel_lambda)
    return (2 * beta / cooling_rate(1.0, alpha, gamma, C, lam, a2, n, d, geometry)) ** (1 / (1 + lam / 2))


def maxwell_steady_temperature(alpha, beta, gamma, C, d=3, geometry=None):
    """T_inf = 2 beta/(gamma pi C (1 - alpha^2)) of Maxwell molecules under white noise, GRW05
    eq. (17) [exact, n -> infinity]; in d = 2 the rate of cooling_rate (2 pi/3 or pi/2 for pi)."""
    return steady_temperature(alpha, beta, gamma, C, 0, d=d, geometry=geometry)


def hard_sphere_steady_temperature(alpha, beta, gamma, C, sonine=True, n=None, d=3, geometry=None):
    """T_inf of heated hard spheres, (2 beta/K)^(2/3), K = 16/3 sqrt(pi) gamma C (1 - alpha^2)
    (1 + 3 a2/16) [approx]: with sonine, a2 the white-noise first-Sonine value (van Noije & Ernst
    1998); without, the Maxwellian estimate (a2 = 0, as the simulator's run-time estimate).  d = 2:
    hard disks, K = pi^(3/2) gamma C (1 - alpha^2)(1 + 3 a2/16) (cooling_rate)."""
    a2 = first_sonine_a2(alpha, "white_noise", 1, d, geometry) if sonine else 0.0
    return steady_temperature(alpha, beta, gamma, C, 1, a2, n, d, geometry)
