r"""Leading-order tail of the uniformly heated steady state, and what GRW05's eq. (38) fit sees.

A particle much faster than the bulk loses its velocity at rate nu_lambda |v|^lambda (each
collision replaces it by a bulk-like velocity), nu_lambda = 4 pi C_lambda gamma (density 1).
Balancing that loss against the diffusion beta Lap_v gives, to leading (WKB) order,
beta (d_r ln f)^2 = nu_lambda r^lambda, so

    f(r) ~ A r^chi exp(-a r^b),   b = 1 + lambda/2,   a = sqrt(nu_lambda / beta) / b

(van Noije & Ernst 1998; Bobylev, Gamba & Panferov 2004 prove b = 3/2 for hard spheres).  For
lambda = 0 the exact moments (granboltz.theory.maxwell_hierarchy) check a: for f ~ r^chi e^{-a r} in 3-D,
M_2p ~ Gamma(2p + 3 + chi) / a^(2p+3+chi), so M_{2p+2}/M_2p -> (2p+3+chi)(2p+4+chi)/a^2.

GRW05 fit y = ln(ln f_k0 - ln f_k) against x = ln(k - k0).  If ln f(0) - ln f(r) = a r^b + C'
(with C' < 0 for a core flatter than the tail's continuation), the local slope is
b / (1 + C'/(a r^b)) = b (1 + |C'|/(a r^b) + ...): the fit is biased upwards by a term that fades
only like 1/(number of e-folds of f) (eq38_slope).
"""
from fractions import Fraction
from math import pi, sqrt

import numpy as np

from .dimension import check_dimension

# GRW05 §5.3: C_lambda = 1/(4 pi), gamma = 16, beta = 30, alpha = 1/10 (Examples 7-9 differ in lambda)
EXAMPLES = {
    7: {"lambda": 0.0, "beta": 30.0, "gamma": 16.0, "pi_c": 0.25, "alpha": 0.1},
    8: {"lambda": 1.0, "beta": 30.0, "gamma": 16.0, "pi_c": 0.25, "alpha": 0.1},
    9: {"lambda": 0.5, "beta": 30.0, "gamma": 16.0, "pi_c": 0.25, "alpha": 0.1},
}


def tail_exponent(lam, d=3):
    """Leading-order tail exponent b = 1 + lambda/2 (GRW05 eqs. 20-21), the same in d = 2."""
    check_dimension(d, (2, 3), "tail_exponent")
    return 1.0 + lam / 2.0


def fast_particle_rate(gamma, pi_c, d=3):
    """nu_lambda = |S^(d-1)| C_lambda gamma (density 1), given gamma and pi*C_lambda: 4 pi C gamma in
    d = 3, 2 pi C gamma in d = 2 (the loss rate of a fast particle, whatever the geometry)."""
    d = check_dimension(d, (2, 3), "fast_particle_rate")
    return (4.0 if d == 3 else 2.0) * gamma * pi_c


def tail_amplitude(nu, beta, lam, d=3):
    """Leading-order tail amplitude a = sqrt(nu_lambda / beta) / b, b = 1 + lambda/2 (any d, given
    the nu_lambda of that d: fast_particle_rate)."""
    return sqrt(nu / beta) / tail_exponent(lam, d)


def example_tail(example):
    """{'b', 'a', 'nu'} of GRW05 Example 7, 8 or 9 (leading order; d = 3, the papers')."""
    e = EXAMPLES[example]
    nu = fast_particle_rate(e["gamma"], e["pi_c"])
    return {"b": tail_exponent(e["lambda"]), "a": tail_amplitude(nu, e["beta"], e["lambda"]), "nu": nu}


def _ratios(moments):
    m = [Fraction(x) for x in moments]  # exact ratios even when the moments exceed 1e308
    return np.array([float(m[p + 1] / m[p]) for p in range(len(m) - 1)])


def amplitude_from_moments(moments, chi=0.0, d=3):
    """Estimates a_p = sqrt((2p+d+chi)(2p+d+1+chi) M_2p / M_{2p+2}), p = 0..len-2, of the amplitude of
    an exponential tail r^chi e^{-a r} in d dimensions (M_2p ~ Gamma(2p+d+chi)/a^(2p+d+chi)), from the
    moments [M_0, M_2, ...]."""
    d = check_dimension(d, (2, 3), "amplitude_from_moments")
    p = np.arange(len(moments) - 1)
    return np.sqrt((2 * p + d + chi) * (2 * p + d + 1 + chi) / _ratios(moments))


def amplitude_and_chi_from_moments(moments, d=3):
    """(a_p, chi_p), p = 0..len-3: a and chi of r^chi e^{-a r} solved exactly from two successive
    ratios R_p = M_{2p+2}/M_2p, R_{p+1}: with x = 2p+3+chi, R_{p+1}/R_p = (x+2)(x+3)/(x(x+1)),
    i.e. (rho - 1) x^2 + (rho - 5) x - 6 = 0, and a^2 = x(x+1)/R_p; in d dimensions x = 2p+d+chi."""
    d = check_dimension(d, (2, 3), "amplitude_and_chi_from_moments")
    R = _ratios(moments)
    rho = R[1:] / R[:-1]
    x = (5 - rho + np.sqrt((rho - 5) ** 2 + 24 * (rho - 1))) / (2 * (rho - 1))
    p = np.arange(len(R) - 1)
    return np.sqrt(x * (x + 1) / R[:-1]), x - 2 * p - d


def local_eq38_slope(a, b, offset, r):
    """d ln(a r^b + C') / d ln r = b / (1 + C'/(a r^b)): the local slope of GRW05's y against ln r
    when ln f(0) - ln f(r) = a r^b + C' (offset = C')."""
    r = np.asarray(r, dtype=float)
    return b / (1.0 + offset / (a * r**b))


def eq38_slope(a, b, offset, radius, shells, k0=1, window=(4.25, 4.6), chi=0.0):
    """Expected least-squares slope of GRW05's eq. (38) fit for a density with
    ln f_k0 - ln f(r) = a r^b - chi ln r + C' (offset = C'), shells k = 1..K of width h = R/K
    evaluated at their midpoints (k - 1/2) h, x = ln(k - k0) on the window (the published one:
    x in [4.25, 4.6], shells 71-100 of 128 for k0 = 1).  Returns the slope b_eff."""
    k = np.arange(k0 + 1, shells + 1)
    x = np.log(k - k0)
    sel = (x >= window[0]) & (x <= window[1])
    r = (k[sel] - 0.5) * radius / shells
    y = np.log(a * r**b - chi * np.log(r) + offset)
    return float(np.polyfit(x[sel], y, 1)[0])


def offset_for_slope(b_eff, a, b, radius, shells, k0=1, window=(4.25, 4.6), chi=0.0):
    """The offset C' for which eq38_slope returns b_eff (scipy brentq; C' between -a r_lo^b and 0
    for b_eff >= b)."""
    from scipy.optimize import brentq

    k_lo = int(np.ceil(np.exp(window[0]) + k0 - 1e-9))
    r_lo = (k_lo - 0.5) * radius / shells
    lo = -(a * r_lo**b - chi * np.log(r_lo)) * (1 - 1e-9)
    hi = (a * r_lo**b) * 10
    return brentq(lambda c: eq38_slope(a, b, c, radius, shells, k0, window, chi) - b_eff, lo, hi, xtol=1e-12)


def importance_split(lam, beta, gamma, C, radius, r_s, power=None, d=3):
    """dsmc.weights.split for a heated steady tail (docs/config.md): the importance function
    exp(-a r^b) of the leading-order tail, splitting from r_s out to the histogram radius R =
    `radius`, sweeps whose kicks move a particle by half an e-fold of it at R, h = 1/(8 beta s^2),
    s = a b R^(b-1).  power: exp(-a' r^power) instead, a' = a R^b / R^power (the same decay at R,
    another shape; the importance check), with the same h.  d: the nu_lambda of fast_particle_rate."""
    a, b = tail_amplitude(fast_particle_rate(gamma, pi * C, d), beta, lam, d), tail_exponent(lam, d)
    slope = a * b * radius ** (b - 1)
    rate, shape = (a, b) if power is None else (a * radius**b / radius ** float(power), float(power))
    return {"radius": float(r_s), "rate": rate, "power": shape, "interval": 1.0 / (8.0 * beta * slope**2),
            "max_radius": radius}
