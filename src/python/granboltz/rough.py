"""Beyond the papers: rough inelastic hard spheres (normal restitution alpha, tangential beta in
[-1, 1], reduced moment of inertia kappa = 4I/(m sigma^2), 2/5 for a uniform sphere), d = 3.  The
Maxwellian two-temperature theory of Huthmann & Zippelius (1997) and Luding et al. (1998), the
ratio theta = T_rot/T_tr it gives in the homogeneous cooling state (HCS) and under white noise on
the translational velocities; the table rows and verdict of the report item (rule beyond_rough).

[approx; reference/beyond.md §5] eta = kappa (1 + beta)/(2 (1 + kappa)),
A = (1 - alpha^2)/4 + eta (1 - eta), B = eta^2/kappa, C = (eta/kappa)(1 - eta/kappa):

    dT_tr/dt  = -(4 nu/3) (A T_tr - B T_rot),
    dT_rot/dt =  (4 nu/3) (B T_tr - C T_rot),   nu = 4 n sigma^2 sqrt(pi T_tr/m).

HCS: both temperatures decay at one rate, so theta solves B theta^2 + (A - C) theta - B = 0,
theta = h + sqrt(1 + h^2), h = (A - C)/(2B), which is
h = (1 + kappa)/(2 kappa (1 + beta)^2) [(1 + kappa)(1 - alpha^2) - (1 - kappa)(1 - beta^2)].
The Gaussian thermostat rescales velocities and spins by one factor (the total energy fixed), so
its steady theta is the HCS one.  White noise heats T_tr only; the rotational equation alone is
then steady at theta = B/C = kappa (1 + beta)/(1 + 2 kappa - beta), independent of alpha.
Known quality (beyond.md §5): in the HCS at alpha = 0.8-0.9 simulations put theta 4-5 % below
this formula; under white noise within 1 %.
"""

import numpy as np

KAPPA_SPHERE = 0.4  # kappa of a uniform solid sphere, I = m sigma^2/10


def _check(beta, kappa):
    if np.any(np.abs(np.asarray(beta, float)) > 1) or np.any(np.asarray(kappa, float) <= 0):
        raise ValueError(f"need -1 <= beta <= 1 and kappa > 0 (beta {beta}, kappa {kappa})")


def coefficients(alpha, beta, kappa=KAPPA_SPHERE):
    """(A, B, C) of the two-temperature equations (module text)."""
    _check(beta, kappa)
    alpha, beta = np.asarray(alpha, float), np.asarray(beta, float)
    eta = kappa * (1 + beta) / (2 * (1 + kappa))
    return (1 - alpha**2) / 4 + eta * (1 - eta), eta**2 / kappa, eta / kappa * (1 - eta / kappa)


def temperature_rates(T_tr, T_rot, alpha, beta, kappa=KAPPA_SPHERE, density=1.0, sigma=1.0, mass=1.0):
    """(dT_tr/dt, dT_rot/dt) of free cooling [approx: Maxwellian], units of the kernel
    B = sigma^2 |g.n| (the simulator's C sigma^2 |u| multiplies both by 4 pi C)."""
    A, B, C = coefficients(alpha, beta, kappa)
    nu = 4 * density * sigma**2 * np.sqrt(np.pi * np.asarray(T_tr, float) / mass)
    return -(4 * nu / 3) * (A * T_tr - B * T_rot), (4 * nu / 3) * (B * T_tr - C * T_rot)


def hcs_theta(alpha, beta, kappa=KAPPA_SPHERE):
    """theta = T_rot/T_tr of the HCS, h + sqrt(1 + h^2) [approx: Huthmann-Zippelius]; for
    beta = -1 (smooth spheres, no coupling) the limit is infinite: NaN is returned there."""
    _check(beta, kappa)
    alpha, beta = np.asarray(alpha, float), np.asarray(beta, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        h = (1 + kappa) / (2 * kappa * (1 + beta) ** 2) * ((1 + kappa) * (1 - alpha**2) - (1 - kappa) * (1 - beta**2))
        theta = h + np.sqrt(1 + h**2)
    return np.where(beta > -1, theta, np.nan)[()]


def white_noise_theta(beta, kappa=KAPPA_SPHERE):
    """theta of white noise on the translational velocities, kappa (1 + beta)/(1 + 2 kappa - beta),
    independent of alpha [approx: Maxwellian]."""
    _check(beta, kappa)
    beta = np.asarray(beta, float)
    return (kappa * (1 + beta) / (1 + 2 * kappa - beta))[()]


def theta(thermostat, alpha, beta, kappa=KAPPA_SPHERE):
    """The Maxwellian theta of a thermostat: "gaussian" (HCS) or "white_noise"."""
    if thermostat == "gaussian":
        return hcs_theta(alpha, beta, kappa)
    if thermostat == "white_noise":
        return white_noise_theta(beta, kappa)
    raise ValueError(f"no steady theta for thermostat {thermostat!r}")
