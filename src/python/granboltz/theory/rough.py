"""Beyond the papers: rough inelastic hard spheres (d = 3) and disks (d = 2): normal restitution
alpha, tangential beta in [-1, 1], reduced moment of inertia kappa = 4I/(m sigma^2) (2/5 a uniform
sphere, 1/2 a uniform disk).  The Maxwellian two-temperature theory of Huthmann & Zippelius (1997)
and Luding et al. (1998), in d dimensions; the ratio theta = T_rot/T_tr it gives in the
homogeneous cooling state (HCS) and under white noise on the translational velocities (the table
rows and verdict of the report item, rule beyond_rough: granboltz.reproduction.rough).

Derivation [approx: both velocities and spins Maxwellian; docs/physics.md, Rough particles].  With
g = v1 - v2, n the impact normal, s the spins' part of the contact velocity and w = g_t + s its
tangential part, the map of reference/beyond.md §5 changes the pair's energies by
    dE_tr = m [-(1 - alpha^2) g_n^2/4 + eta^2 |w|^2 - eta w.g_t],
    dE_rot = m [(eta^2/kappa) |w|^2 - eta w.s],       eta = kappa (1 + beta)/(2 (1 + kappa)).
Averaged over impacts (weight (g.n)+, the hard-sphere and hard-disk law: geometry "impact") with
g Maxwellian (variance 2T/m per component) and independent spins: <g_n^2> = 4T/m in every d,
<|g_t|^2> = 2(d-1) T/m, <|s|^2> = 2(d-1) T_rot/(kappa m) (d - 1 tangential directions; d_rot = 3
spin components in d = 3, 1 in d = 2), <g_t.s> = 0.  With the collision frequency nu per particle
and the energies d T/2, d_rot T_rot/2 per particle:
    dT_tr/dt  = -(2(d-1) nu/d) (A T_tr - B T_rot),      A = (1 - alpha^2)/(2(d-1)) + eta (1 - eta),
    dT_rot/dt =  (2(d-1) nu/d_rot) (B T_tr - C T_rot),  B = eta^2/kappa, C = (eta/kappa)(1 - eta/kappa),
d = 3 (4 nu/3 both, A = (1 - alpha^2)/4 + ...): beyond.md §5; d = 2: nu (A = (1 - alpha^2)/2 + ...)
and 2 nu.  nu = n sigma^(d-1) pi^((d-1)/2) 2 sqrt(T_tr/m)/Gamma(d/2): 4 n sigma^2 sqrt(pi T/m) (d = 3),
2 n sigma sqrt(pi T/m) (d = 2).  The initial rates from a Maxwellian are exact (test_rough_theory).
HCS: both decay at one rate, so with r = d_rot/d, r B theta^2 + (C - r A) theta - B = 0,
    theta = h + sqrt(h^2 + 1/r),  h = (r A - C)/(2 r B),
in d = 3 h + sqrt(1 + h^2), h = (1 + kappa)/(2 kappa (1 + beta)^2) [(1 + kappa)(1 - alpha^2) - (1 - kappa)(1 - beta^2)];
in d = 2 h + sqrt(2 + h^2), h = (A - 2C)/(2B).  The Gaussian thermostat rescales velocities and spins
by one factor (the total energy fixed), so its steady theta is the HCS one.  White noise heats T_tr
only; the rotational equation alone is then steady at theta = B/C = kappa (1 + beta)/(1 + 2 kappa - beta)
in every d.  Limits: alpha = beta = 1 gives A = B = C and theta = 1 (equipartition) in every d;
beta = -1 (smooth) gives B = C = 0, T_rot constant, no steady theta (NaN).
Known quality (beyond.md §5): in the HCS at alpha = 0.8-0.9 simulations put theta 4-5 % below
this formula; under white noise within 1 %.  This project's runs (rule beyond_rough, quick
profile) agree with the first for beta = 0 (-4.6 % at alpha = 0.9) but find the gap shrinking
with beta (-1.8 % at 0.5, +0.1 % at 0.9) and growing at stronger dissipation (-8 % at
alpha = 0.7 and 0.5, beta = 0); under white noise they find -2.5 % (beta = 0), -1.4 % (0.5) and
-0.3 % (0.9): beyond 1 % for beta <= 0.5, a disagreement with beyond.md's account.  Rough disks
(d = 2, kappa = 1/2, this simulator; docs/physics.md): HCS beta = 0 -5.3 % (alpha = 0.9), -9.4 %
(0.7), -13.5 % (0.5); beta = 0.5 -2.5, -4.2, -5.8 %; beta = 0.9 -0.4, -0.1 %; white noise -3.0,
-2.1, -0.7 % (beta = 0, 0.5, 0.9).  The d = 3 formula is 12-64 % above them at beta <= 0.5.
"""

import numpy as np

from .dimension import check_dimension, check_geometry


KAPPA_SPHERE = 0.4  # kappa of a uniform solid sphere, I = m sigma^2/10


KAPPA_DISK = 0.5  # kappa of a uniform disk, I = m sigma^2/8


def _setup(what, beta, kappa, d, geometry):
    """(d, kappa) checked: d 2 or 3, geometry impact in d = 2, -1 <= beta <= 1, kappa > 0 (None:
    the uniform sphere or disk of d)."""
    d = check_dimension(d, (2, 3), what)
    check_geometry(d, geometry, what)
    kappa = (KAPPA_SPHERE if d == 3 else KAPPA_DISK) if kappa is None else kappa
    if np.any(np.abs(np.asarray(beta, float)) > 1) or np.any(np.asarray(kappa, float) <= 0):
        raise ValueError(f"{what}: need -1 <= beta <= 1 and kappa > 0 (beta {beta}, kappa {kappa})")
    return d, kappa


def coefficients(alpha, beta, kappa=None, d=3, geometry=None):
    """(A, B, C) of the two-temperature equations in d dimensions (module text)."""
    d, kappa = _setup("rough.coefficients", beta, kappa, d, geometry)
    alpha, beta = np.asarray(alpha, float), np.asarray(beta, float)
    eta = kappa * (1 + beta) / (2 * (1 + kappa))
    normal = (1 - alpha**2) / 4 if d == 3 else (1 - alpha**2) / 2
    return normal + eta * (1 - eta), eta**2 / kappa, eta / kappa * (1 - eta / kappa)


def temperature_rates(T_tr, T_rot, alpha, beta, kappa=None, density=1.0, sigma=1.0, mass=1.0, d=3,
                      geometry=None):
    """(dT_tr/dt, dT_rot/dt) of free cooling [approx: Maxwellian; exact at a Maxwellian state], in
    units of the hard-sphere (hard-disk) kernel sigma^(d-1) (g.n)+ per unit solid angle; the
    simulator's gamma C sigma^(d-1) |u| with the impact law multiplies both by 4 gamma C (d = 3) or
    pi gamma C (d = 2)."""
    A, B, C = coefficients(alpha, beta, kappa, d, geometry)
    T = np.asarray(T_tr, float)
    if d == 3:
        nu = 4 * density * sigma**2 * np.sqrt(np.pi * T / mass)
        return -(4 * nu / 3) * (A * T_tr - B * T_rot), (4 * nu / 3) * (B * T_tr - C * T_rot)
    nu = 2 * density * sigma * np.sqrt(np.pi * T / mass)
    return -nu * (A * T_tr - B * T_rot), 2 * nu * (B * T_tr - C * T_rot)


def hcs_theta(alpha, beta, kappa=None, d=3, geometry=None):
    """theta = T_rot/T_tr of the HCS [approx: Maxwellian, Huthmann-Zippelius in d dimensions]:
    h + sqrt(1 + h^2) in d = 3, h + sqrt(2 + h^2) in d = 2 (module text); for beta = -1 (smooth,
    no coupling) the limit is infinite: NaN is returned there."""
    d, kappa = _setup("rough.hcs_theta", beta, kappa, d, geometry)
    alpha, beta = np.asarray(alpha, float), np.asarray(beta, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        if d == 3:
            h = (1 + kappa) / (2 * kappa * (1 + beta) ** 2) * ((1 + kappa) * (1 - alpha**2) - (1 - kappa) * (1 - beta**2))
            theta = h + np.sqrt(1 + h**2)
        else:
            A, B, C = coefficients(alpha, beta, kappa, 2)
            h = (A - 2 * C) / (2 * B)
            theta = h + np.sqrt(2 + h**2)
    return np.where(beta > -1, theta, np.nan)[()]


def white_noise_theta(beta, kappa=None, d=3, geometry=None):
    """theta of white noise on the translational velocities, kappa (1 + beta)/(1 + 2 kappa - beta),
    independent of alpha and the same in d = 2 and 3 [approx: Maxwellian]."""
    d, kappa = _setup("rough.white_noise_theta", beta, kappa, d, geometry)
    beta = np.asarray(beta, float)
    return (kappa * (1 + beta) / (1 + 2 * kappa - beta))[()]


def theta(thermostat, alpha, beta, kappa=None, d=3, geometry=None):
    """The Maxwellian theta of a thermostat: "gaussian" (HCS) or "white_noise"."""
    if thermostat == "gaussian":
        return hcs_theta(alpha, beta, kappa, d, geometry)
    if thermostat == "white_noise":
        return white_noise_theta(beta, kappa, d, geometry)
    raise ValueError(f"no steady theta for thermostat {thermostat!r}")
