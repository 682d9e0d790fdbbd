"""Beyond the papers: binary (and larger) mixtures of inelastic hard spheres (d = 3) and hard disks
(d = 2), dilute.  The Maxwellian partial cooling rates of Garzó & Dufty (1999) and the temperature
ratios they give in the homogeneous cooling state (HCS) and under white noise; the Martin-Piasecki
tracer limit (the table rows and verdict of the report item, rule beyond_mixture: granboltz.reproduction.mixtures).

Partial cooling rates [approx: every species Maxwellian at its own T_i; reference/beyond.md §4]:

    zeta_i = K_d sum_j n_j sigma_ij^(d-1) mu_ji (1 + a_ij) (2 T_i/m_i + 2 T_j/m_j)^(1/2)
             [1 - mu_ji (1 + a_ij) (1 + m_i T_j/(m_j T_i)) / 2],   mu_ji = m_j/(m_i + m_j),

K_d = 4 pi^((d-1)/2)/(d Gamma(d/2)) (8 sqrt(pi)/3 in d = 3, 2 sqrt(pi) in d = 2: Garzó-Dufty's d
dimensions; the impact law, (g.n)+, whose <g_n^2> over impacts is the same in d = 2 and 3, so d
enters only through K_d and sigma_ij^(d-1)), sigma_ij = (sigma_i + sigma_j)/2, dT_i/dt = -zeta_i
T_i (units of the standard kernel B = sigma_ij^(d-1) |g.n|; the simulator's C sigma_ij^(d-1) |u|
scales every zeta_i by one factor, which no ratio depends on; with equal diameters the ratios are
the same in d = 2 and 3).  HCS: zeta_1 = zeta_2 = ... (every T_i decays at one rate, so T_i/T is steady;
the Gaussian thermostat, which rescales all velocities by one factor, keeps exactly these ratios).
White noise with the same velocity-kick variance xi^2 for every particle: dT_i/dt = m_i xi^2 -
zeta_i T_i, so zeta_i T_i/m_i is the same for all i.

The ratios are returned as gamma_i = T_i/T with T = sum_i x_i T_i (the mixture's temperature, as
the simulator's /temperature).  The conditions are homogeneous in the T_i (zeta_i ~ T^(1/2)), so
T_1 is fixed and scipy.optimize.root solves for log(T_i/T_1), i >= 2.  Every number of the HCS
table and of the white-noise list of beyond.md §4 is reproduced to four decimals
(tests/python/reproduction/test_mixtures.py), and the tracer limit gives Martin-Piasecki.  The simulator's
HCS (rule beyond_mixture, quick profile, m1/m2 = 2 and 4) puts T1/T2 0.2-1.0 % below these
ratios at every alpha from 0.95 to 0.5.
"""

import math

import numpy as np

from .dimension import check_dimension, check_geometry


def _matrix(alpha, s):
    """alpha as an s x s symmetric matrix: one number for every pair, or the matrix itself."""
    a = np.asarray(alpha, dtype=float)
    if a.ndim == 0:
        return np.full((s, s), float(a))
    if a.shape != (s, s) or not np.allclose(a, a.T):
        raise ValueError(f"alpha must be one number or a symmetric {s} x {s} matrix, not {a.tolist()}")
    return a


def _species(masses, fractions, diameters):
    m = np.asarray(masses, dtype=float)
    x = np.asarray(fractions, dtype=float)
    sig = np.ones_like(m) if diameters is None else np.asarray(diameters, dtype=float)
    if not (m.ndim == 1 and m.shape == x.shape == sig.shape and m.size >= 1):
        raise ValueError("masses, fractions and diameters need one entry per species")
    if np.any(m <= 0) or np.any(sig <= 0) or np.any(x < 0) or not math.isclose(x.sum(), 1.0, rel_tol=1e-9):
        raise ValueError("masses and diameters must be positive, fractions non-negative and sum to 1")
    return m, x, sig


def _dimension(what, d, geometry):
    d = check_dimension(d, (2, 3), what)
    check_geometry(d, geometry, what)
    return d


def partial_cooling_rates(temperatures, masses, fractions, alpha, diameters=None, density=1.0, d=3, geometry=None):
    """zeta_i of Garzó-Dufty (Maxwellian species; see the module text) for the species
    temperatures T_i, masses m_i, number fractions x_i (n_i = x_i density), alpha (one value or a
    symmetric matrix alpha_ij) and diameters sigma_i (default 1), in d = 3 or 2 (impact law)."""
    d = _dimension("partial_cooling_rates", d, geometry)
    m, x, sig = _species(masses, fractions, diameters)
    T = np.asarray(temperatures, dtype=float)
    a = _matrix(alpha, m.size)
    sij = (sig[:, None] + sig[None, :]) / 2
    mu_ji = m[None, :] / (m[:, None] + m[None, :])  # [i, j] = m_j/(m_i + m_j)
    speed = np.sqrt(2 * T[:, None] / m[:, None] + 2 * T[None, :] / m[None, :])
    ratio = m[:, None] * T[None, :] / (m[None, :] * T[:, None])  # m_i T_j/(m_j T_i)
    terms = (density * x[None, :] * (sij**2 if d == 3 else sij) * mu_ji * (1 + a) * speed
             * (1 - 0.5 * mu_ji * (1 + a) * (1 + ratio)))
    return (8 * math.sqrt(math.pi) / 3 if d == 3 else 2 * math.sqrt(math.pi)) * terms.sum(axis=1)


def _solve(residual, s):
    """Roots y (s - 1 values, y_i = log(T_{i+1}/T_1)) of residual(y) -> [s - 1]: scipy.optimize.root
    (Powell's hybrid method) from equipartition; RuntimeError if it does not converge."""
    from scipy.optimize import root

    sol = root(residual, np.zeros(s - 1), method="hybr", tol=1e-13)
    if np.max(np.abs(residual(sol.x))) > 1e-10:  # "no further improvement" at the tolerance is success
        raise RuntimeError(f"temperature ratios did not converge: {sol.message}")
    return sol.x


def _frequencies(T, m, x, sig, d):
    """nu_i = sum_j x_j sigma_ij^(d-1) (2 T_i/m_i + 2 T_j/m_j)^(1/2): the scale of zeta_i (never 0)."""
    sij = (sig[:, None] + sig[None, :]) / 2
    return (x[None, :] * (sij**2 if d == 3 else sij) * np.sqrt(2 * T[:, None] / m[:, None] + 2 * T[None, :] / m[None, :])).sum(axis=1)


def _ratios(masses, fractions, alpha, diameters, heated, d):
    """gamma_i = T_i/T where zeta_i (heated: zeta_i T_i/m_i) is the same for every species."""
    m, x, sig = _species(masses, fractions, diameters)
    a = _matrix(alpha, m.size)
    if m.size == 1:
        return np.ones(1)

    def residual(y):
        T = np.exp(np.concatenate([[0.0], y]))
        weight = T / m if heated else np.ones_like(T)
        q = partial_cooling_rates(T, m, x, a, sig, d=d) * weight
        scale = _frequencies(T, m, x, sig, d) * weight  # differences relative to it: fine where zeta = 0 (alpha = 1)
        return (q[1:] - q[0]) / (scale[1:] + scale[0])

    T = np.exp(np.concatenate([[0.0], _solve(residual, m.size)]))
    return T / np.dot(x, T)


def hcs_temperature_ratios(masses, fractions, alpha, diameters=None, d=3, geometry=None):
    """gamma_i = T_i/T (T = sum x_i T_i) of the homogeneous cooling state, zeta_1 = zeta_2 = ...
    [approx: Garzó-Dufty 1999, Maxwellian species]; T1/T2 = gamma[0]/gamma[1]."""
    return _ratios(masses, fractions, alpha, diameters, False, _dimension("hcs_temperature_ratios", d, geometry))


def white_noise_temperature_ratios(masses, fractions, alpha, diameters=None, d=3, geometry=None):
    """gamma_i = T_i/T of the white-noise steady state with the same velocity-kick variance for
    every particle (Barrat-Trizac): zeta_i T_i/m_i equal for all i [approx: Garzó-Dufty rates]."""
    return _ratios(masses, fractions, alpha, diameters, True, _dimension("white_noise_temperature_ratios", d, geometry))


def temperature_ratio(thermostat, mass_ratio, alpha, x1=0.5, diameter_ratio=1.0, d=3, geometry=None):
    """T1/T2 of two species with m1/m2 = mass_ratio, fraction x1 of species 1, common alpha and
    sigma1/sigma2 = diameter_ratio: thermostat "gaussian" (HCS) or "white_noise"."""
    solve = {"gaussian": hcs_temperature_ratios, "white_noise": white_noise_temperature_ratios}[thermostat]
    g = solve([float(mass_ratio), 1.0], [x1, 1 - x1], alpha, [float(diameter_ratio), 1.0], d, geometry)
    return float(g[0] / g[1])


def martin_piasecki(alpha0, mass_ratio, d=3):
    """T0/T of an inelastic tracer (restitution alpha0 with the bath, mass m0) in an elastic bath
    of temperature T and particle mass m, mass_ratio = m/m0 [approx: Maxwellian tracer]:
    (1 + alpha0)/(2 + (1 - alpha0) m/m0) (Martin & Piasecki 1999; the TV06 curve), the same in
    d = 1, 2 and 3 (the tracer limit of partial_cooling_rates, whose d is a common factor)."""
    check_dimension(d, (1, 2, 3), "martin_piasecki")
    return (1 + alpha0) / (2 + (1 - alpha0) * mass_ratio)
