"""Closed-form and exact theory: the temperature of the heated Maxwell gas (GRW05 eqs. 16-17),
the exact means of the Euler and Strang schemes (RW05) and of the papers' temperature estimator,
and the TV06 formulas of §3.1 (baths, collision rates, colliding densities, the Martin-Piasecki
temperature ratio).

TV06 equation numbers are those of the pdf text (docs/tv06.md); bath particles have m = 1.
"""

import math

import numpy as np
from scipy import integrate, special, stats

from .dimension import check_dimension, check_geometry, dsmc_geometry, initial_temperature

from . import LAMBDA_P


# ----------------------------------------------------------------------------- GRW05 / RW05
def maxwell_rate(alpha, gamma, C0, d=3, geometry=None):
    """k of dT/dt = 2 beta - k T for Maxwell molecules (lambda = 0) [exact]: gamma pi C0 (1 -
    alpha^2) in d = 3 (GRW05 eq. 16); in d = 2 (2 pi/3) gamma C0 (1 - alpha^2) for disk impacts
    and (pi/2) gamma C0 (1 - alpha^2) for the uniform law (granboltz.theory.sonine.cooling_rate)."""
    d = check_dimension(d, (2, 3), "maxwell_rate")
    geometry = check_geometry(d, geometry, "maxwell_rate", ("impact", "uniform"))
    if d == 3:
        return gamma * math.pi * C0 * (1.0 - alpha**2)
    return gamma * math.pi * (2 / 3 if geometry == "impact" else 1 / 2) * C0 * (1.0 - alpha**2)


def analytic_temperature(t, T0, alpha, beta, gamma, C0, d=3, geometry=None):
    """Temperature of the heated Maxwell-pseudomolecule gas, GRW05 eqs. (16), (17).

    T(t) = T0 e^{-k t} + T_inf (1 - e^{-k t}), k = gamma pi C0 (1 - alpha^2) (d = 3; maxwell_rate
    in d = 2), T_inf = 2 beta / k; for alpha = 1 (k = 0) the limit T0 + 2 beta t.
    """
    t = np.asarray(t, dtype=float)
    k = maxwell_rate(alpha, gamma, C0, d, geometry)
    if k == 0.0:
        return T0 + 2.0 * beta * t
    decay = np.exp(-k * t)
    return T0 * decay + (2.0 * beta / k) * (1.0 - decay)


def dsmc_physics(dsmc):
    """(T0, alpha, beta, gamma, C0) of a run config's dsmc section (lambda must be 0)."""
    if dsmc["kernel"]["lambda"] != 0:
        raise ValueError(f"eq. (16) needs kernel lambda = 0, got {dsmc['kernel']['lambda']}")
    T0 = initial_temperature(dsmc)  # eq. (16) is closed in T: exact from any start of that T
    return T0, dsmc["alpha"], dsmc["beta"], dsmc.get("gamma", 1.0), dsmc["kernel"]["C"]


def run_analytic_temperature(run):
    """Eq. (16) with the parameters the run was made with, in its d (lambda must be 0: eq. 16 is
    exact for Maxwell pseudomolecules only)."""
    try:
        return analytic_temperature(run.time, *dsmc_physics(run.dsmc), *dsmc_geometry(run.dsmc))
    except ValueError as err:
        raise ValueError(f"{run.path}: {err}") from None


def scheme_temperature(scheme, t, dt, T0, alpha, beta, gamma, C0, d=3, geometry=None):
    """Mean temperature of a scheme as n -> infinity at the times t (multiples of dt), Maxwell
    molecules: no-splitting is eq. (16); one Euler step (RW05 Alg. 1: collisions, then kicks)
    maps T to e^{-k dt} T + 2 beta dt, one Strang step to e^{-k dt/2}(e^{-k dt/2} T + 2 beta dt),
    with k = gamma pi C0 (1 - alpha^2) (maxwell_rate in d = 2). Observations follow a whole step."""
    t = np.atleast_1d(np.asarray(t, dtype=float))
    if scheme == "nosplit":
        return analytic_temperature(t, T0, alpha, beta, gamma, C0, d, geometry)
    k = maxwell_rate(alpha, gamma, C0, d, geometry)
    a, b = math.exp(-k * dt), 2.0 * beta * dt
    if scheme == "strang":
        b *= math.exp(-k * dt / 2)
    elif scheme != "euler":
        raise ValueError(f"unknown scheme {scheme!r}")
    steps = np.rint(t / dt).astype(int)
    if np.any(np.abs(steps * dt - t) > 1e-9 * np.maximum(1.0, t)):
        raise ValueError("observation times must be multiples of dt")
    # T_k = a^k T0 + b (1 - a^k) / (1 - a)
    ak = a ** steps.astype(float)
    return ak * T0 + (b * steps if a == 1.0 else b * (1.0 - ak) / (1.0 - a))


def scheme_steady_temperature(scheme, dt, alpha, beta, gamma, C0, d=3, geometry=None):
    """Stationary mean temperature of a scheme as n -> infinity (fixed point of the step maps of
    scheme_temperature; no-splitting: T_inf = 2 beta / k, GRW05 eq. 17, RW05 eq. 25)."""
    k = maxwell_rate(alpha, gamma, C0, d, geometry)
    if scheme == "nosplit":
        return 2.0 * beta / k
    T = 2.0 * beta * dt / (1.0 - math.exp(-k * dt))
    return T * math.exp(-k * dt / 2) if scheme == "strang" else T


def uncentred_expectation(T_mean, t, T0, beta, n, d=3):
    """E of the uncentred estimator |v|^2/d of an n-particle system whose mean temperature (n ->
    infinity) is T_mean at time t: (1 - 1/n) T_mean + (T0 + 2 beta t)/n, the same in d = 2 and 3.
    The centred part has the exact bias -T/n (Maxwell molecules); |V|^2/d adds (T0 + 2 beta t)/n,
    since collisions conserve momentum and the kicks make V a random walk of variance 2 beta t/n
    per component."""
    check_dimension(d, (2, 3), "uncentred_expectation")
    return (1.0 - 1.0 / n) * np.asarray(T_mean) + (T0 + 2.0 * beta * np.asarray(t)) / n


def expected_error(run):
    """max_m |E T_m - T(t_m)| / T(t_m): the relative error of the uncentred estimator the run's
    scheme would have with N -> infinity (the systematic part of E_max), and the same at t_end."""
    T0, alpha, beta, gamma, C0 = dsmc_physics(run.dsmc)
    d, geometry = dsmc_geometry(run.dsmc)
    exact = run_analytic_temperature(run)
    mean = scheme_temperature(run.scheme, run.time, run.dt, T0, alpha, beta, gamma, C0, d, geometry)
    err = np.abs(uncentred_expectation(mean, run.time, T0, beta, run.n, d) - exact) / exact
    return float(err.max()), float(err[-1])


# ----------------------------------------------------------------------------- TV06 §3.1
def gaussian_pdf(v, a):
    """Gaussian bath f(v, a) = sqrt(a/pi) exp(-a v^2), eq. (14); T_B = <v^2> = 1/(2a)."""
    return np.sqrt(a / np.pi) * np.exp(-a * np.asarray(v, float) ** 2)


def powerlaw_pdf(v, a):
    """Power-law bath f(v, a) = sqrt(2a)/pi / (1 + a^2 v^4), eq. (19); T_B = <v^2> = 1/a."""
    return math.sqrt(2.0 * a) / np.pi / (1.0 + a**2 * np.asarray(v, float) ** 4)


def gaussian_fluxes(v1, a, rho=1.0):
    """Collision rates (phi_+, phi_-, phi) of an intruder moving at v1 in the Gaussian bath,
    eqs. (15)-(16): phi_± = rho/2 (±v1 + exp(-a v1^2)/sqrt(pi a) + v1 erf(v1 sqrt(a))),
    phi = phi_+ + phi_-. Written with erfc (v1 (1 ± erf x) = v1 erfc(∓x)), the same functions
    without the cancellation of (15) in the rate of the trailing side at large |v1|."""
    v1 = np.asarray(v1, float)
    e, x = np.exp(-a * v1**2) / np.sqrt(np.pi * a), v1 * np.sqrt(a)
    plus, minus = rho / 2 * (e + v1 * special.erfc(-x)), rho / 2 * (e - v1 * special.erfc(x))
    return plus, minus, plus + minus


def fluxes_by_quadrature(v1, a, rho=1.0):
    """(phi_+, phi_-) of eqs. (5)-(6) by numerical quadrature (scipy quad), for checking (15)."""
    plus = integrate.quad(lambda v: (v1 - v) * gaussian_pdf(v, a), -np.inf, v1, epsabs=1e-14, epsrel=1e-13)[0]
    minus = integrate.quad(lambda v: (v - v1) * gaussian_pdf(v, a), v1, np.inf, epsabs=1e-14, epsrel=1e-13)[0]
    return rho * plus, rho * minus


def colliding_density(v, v1, a, rho=1.0, side=+1):
    """Density of the velocity v of the bath particle hitting an intruder moving at v1, Gaussian
    bath: g_+ = rho (v1 - v) f(v) / phi_+(v1) for v <= v1 (eq. 12), g_- = rho (v - v1) f(v) /
    phi_-(v1) for v >= v1 (eq. 13). (The paper prints them without rho, i.e. for rho = 1; with
    it they integrate to 1 for any rho.)"""
    v = np.asarray(v, float)
    plus, minus, _ = gaussian_fluxes(v1, a, rho)
    if side > 0:
        return np.where(v <= v1, rho * (v1 - v) * gaussian_pdf(v, a) / plus, 0.0)
    return np.where(v >= v1, rho * (v - v1) * gaussian_pdf(v, a) / minus, 0.0)


def colliding_mass(v1, a, lo, hi, side=+1):
    """Probability that the colliding velocity of eqs. (12)/(13) lies in [lo, hi] (quadrature)."""
    lo, hi = (max(lo, v1), hi) if side < 0 else (lo, min(hi, v1))
    if hi <= lo:
        return 0.0
    return integrate.quad(lambda v: float(colliding_density(v, v1, a, side=side)), lo, hi, epsabs=1e-15)[0]


def gaussian_temperature_ratio(alpha, M):
    """T/T_B of the intruder in a Gaussian bath (Martin and Piasecki), eq. (18):
    (1 + alpha) / (2 + (1 - alpha)/M)."""
    alpha = np.asarray(alpha, float)
    return (1.0 + alpha) / (2.0 + (1.0 - alpha) / M)


def exact_temperature_ratio(bath, alpha, M):
    """The exact T/T_B where one is known: eq. (18) for the Gaussian bath; alpha at M = alpha for
    any bath (eq. 17: the intruder takes the colliding velocity, its distribution is f itself,
    so T = M <v^2> = alpha T_B); None otherwise."""
    if bath == "gaussian":
        return float(gaussian_temperature_ratio(alpha, M))
    return float(alpha) if math.isclose(alpha, M, rel_tol=1e-12) else None


def t_coverage(N, lambda_p=LAMBDA_P):
    """Probability that the mean of N normal values lies within the simulator's ci of its
    expectation, ci = lambda_p sqrt(var/N) with var the variance over the ensembles (1/N
    normalisation): P(|t_{N-1}| <= lambda_p sqrt((N-1)/N)) (0.986 for N = 10, 0.9986 as N grows)."""
    return float(1.0 - 2.0 * stats.t.sf(lambda_p * math.sqrt((N - 1) / N), N - 1)) if N > 1 else float("nan")



# ----------------------------------------------------------------------------- Sonine theory
# Kept in granboltz.theory.sonine (with its references); its public names are also theory's, where a
# reader looks for the steady temperature and a2, a3 of hard spheres and of Maxwell molecules.
from .sonine import (  # noqa: E402,F401
    cooling_rate,
    first_sonine_a2,
    hard_sphere_steady_temperature,
    hcs_moment_threshold,
    maxwell_a2,
    maxwell_a3,
    maxwell_steady_temperature,
    second_sonine,
    sonine_from_moments,
    steady_temperature,
)
