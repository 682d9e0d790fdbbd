"""Uniform shear flow (USF) and the drag thermostat: the exact second moments of Maxwell
molecules (lambda = 0) and the Grad and first-Sonine approximations for hard spheres.

Conventions as the simulator's (docs/physics.md, "Free flight: drag and shear flow"): density 1,
collision term gamma Q with B = C |u|^lambda, e uniform on S^{d-1} (geometry uniform) for
lambda = 0, the flow u = a y e_x seen from its frame (dv_x/dt = -a v_y between collisions),
drag dv = -gamma_d v dt, white noise of strength beta. nu = |S^{d-1}| gamma C is the per-particle
collision rate of Maxwell molecules; nu0 = (64/5) sqrt(pi) gamma C sqrt(T) that of hard spheres
(p/eta0). Labels: [exact] a result of the Boltzmann equation, [approx] a closure.
"""

import math

import numpy as np
from scipy import integrate, optimize

from .dimension import check_dimension, check_geometry


def _area(d):
    return 4 * math.pi if d == 3 else 2 * math.pi


def maxwell_second_moment_rate(C, alpha, nu, shear=0.0, drag=0.0, beta=0.0, n=None, d=3, geometry="uniform"):
    """dC/dt of the centred second moments C = <(v - V)(v - V)^T> (a d x d array) for lambda = 0,
    geometry uniform [exact, for any n] (C a number: C I): (nu/2)[(4p^2 - 1) C + (4 b^2/d) tr C I]
    - a (E C + C E^T) - 2 gamma_d C + 2 beta (1 - 1/n) I, p = (1-alpha)/4, b = (1+alpha)/4,
    E = e_x e_y^T (n=None: the Boltzmann limit, no 1/n)."""
    d = check_dimension(d, (2, 3), "maxwell_second_moment_rate")
    check_geometry(d, geometry, "maxwell_second_moment_rate", ("uniform",))
    C = np.asarray(C, dtype=float)
    C = C * np.eye(d) if C.ndim == 0 else C.reshape(d, d)  # a number: the isotropic T I
    p, b = (1 - alpha) / 4, (1 + alpha) / 4
    E = np.zeros((d, d))
    E[0, 1] = 1.0
    noise = 2 * beta * (1 - (1 / n if n else 0.0))
    return (0.5 * nu * ((4 * p * p - 1) * C + 4 * b * b / d * np.trace(C) * np.eye(d))
            - shear * (E @ C + C @ E.T) - 2 * drag * C + noise * np.eye(d))


def maxwell_second_moments(t, alpha, gamma, C, shear=0.0, drag=0.0, beta=0.0, T0=1.0, n=None,
                           d=3, geometry="uniform"):
    """E[P(t)] (d x d for each t) of a lambda = 0 gas started from the Maxwellian at T0 [exact]:
    the linear equation of maxwell_second_moment_rate solved by its matrix exponential; with n,
    the n-particle system's centred moments (E[P(0)] = (1 - 1/n) T0 I)."""
    d = check_dimension(d, (2, 3), "maxwell_second_moments")
    check_geometry(d, geometry, "maxwell_second_moments", ("uniform",))
    nu = _area(d) * gamma * C
    start = (1 - (1 / n if n else 0.0)) * T0 * np.eye(d)
    # The map is affine in C: solve the flattened system with an exact integrator.
    def f(_t, y):
        return maxwell_second_moment_rate(y.reshape(d, d), alpha, nu, shear, drag, beta, n,
                                          d).ravel()
    ts = np.atleast_1d(np.asarray(t, dtype=float))
    sol = integrate.solve_ivp(f, (0.0, float(ts.max())), start.ravel(), t_eval=np.sort(ts),
                              rtol=1e-12, atol=1e-14, method="DOP853")
    out = sol.y.T.reshape(-1, d, d)[np.argsort(np.argsort(ts))]
    return out if np.ndim(t) else out[0]


def maxwell_steady_shear_rate(alpha, gamma, C, d=3, geometry="uniform"):
    """a_s: the one shear rate at which USF of Maxwell molecules keeps T constant without a
    thermostat [exact]: nu (3 - alpha) sqrt(k (1 - alpha^2))/8, k = d (3 in d = 3, 2 in d = 2)."""
    d = check_dimension(d, (2, 3), "maxwell_steady_shear_rate")
    check_geometry(d, geometry, "maxwell_steady_shear_rate", ("uniform",))
    nu = _area(d) * gamma * C
    return nu * (3 - alpha) * math.sqrt(d * (1 - alpha * alpha)) / 8


def maxwell_usf_ratios(alpha, d=3, geometry="uniform"):
    """P/p of steady USF of Maxwell molecules at a_s [exact] (transport.md §2): a dict with
    xx, yy, zz (d = 3), xy."""
    d = check_dimension(d, (2, 3), "maxwell_usf_ratios")
    check_geometry(d, geometry, "maxwell_usf_ratios", ("uniform",))
    yy = (1 + alpha) / (3 - alpha)
    out = {"yy": yy, "xy": -math.sqrt(d * (1 - alpha * alpha)) / (3 - alpha),
           "xx": d - (d - 1) * yy}
    if d == 3:
        out["zz"] = yy
    return out


def maxwell_gaussian_usf_ratios(alpha, shear, gamma, C, d=3, geometry="uniform"):
    """P/p of steady USF of Maxwell molecules under the Gaussian thermostat at any shear rate
    [exact]: the dominant eigenvector of the unthermostatted second-moment equation, as a d x d
    array normalised to tr/d = 1."""
    d = check_dimension(d, (2, 3), "maxwell_gaussian_usf_ratios")
    check_geometry(d, geometry, "maxwell_gaussian_usf_ratios", ("uniform",))
    nu = _area(d) * gamma * C
    basis = np.eye(d * d)
    L = np.stack([maxwell_second_moment_rate(basis[k].reshape(d, d), alpha, nu, shear, d=d).ravel()
                  for k in range(d * d)], axis=1)
    w, v = np.linalg.eig(L)
    vec = np.real(v[:, np.argmax(np.real(w))]).reshape(d, d)
    return vec / (np.trace(vec) / d)


def hard_sphere_nu0(T, gamma, C, d=3):
    """nu0 = p/eta0 of elastic hard spheres (d = 3: (64/5) sqrt(pi) gamma C sqrt(T)) or disks
    (d = 2: 2 pi^(3/2) gamma C sqrt(T)) at T, density 1 (transport.md)."""
    d = check_dimension(d, (2, 3), "hard_sphere_nu0")
    factor = 64 / 5 * math.sqrt(math.pi) if d == 3 else 2 * math.pi ** 1.5
    return factor * gamma * C * math.sqrt(T)


def hard_sphere_usf_grad(alpha, shear, gamma, C, d=3):
    """Steady USF of hard spheres (d = 3, no thermostat) in the nonlinear Grad closure
    (transport.md §2) [approx]: J_ij/p = -nu_eta [Pi_ij + ((Pi.Pi)_ij - (Pi:Pi) delta_ij/3)/14]
    - zeta0 (1 + Pi:Pi/40) delta_ij, nu_eta = (3-alpha)(1+alpha)/4 nu0, zeta0 = (5/12)(1 - alpha^2)
    nu0, Pi = P/p - I, balanced by a (delta_ix P_yj + delta_jx P_yi). Returns a dict: T, the
    reduced shear rate a/nu0(T), and P/p as xx, yy, zz, xy."""
    check_dimension(d, (3,), "hard_sphere_usf_grad")

    # In nu0 units the balance does not involve T: solve for Pi and the reduced shear rate a*,
    # then T follows from a* = a/nu0(T), nu0 ~ sqrt(T).
    def residual(x):
        r, pxx, pyy, pxy = x
        Pi = np.array([[pxx, pxy, 0.0], [pxy, pyy, 0.0], [0.0, 0.0, -pxx - pyy]])
        P = np.eye(3) + Pi
        drift = np.zeros((3, 3))
        drift[0, :] += r * P[1, :]
        drift[:, 0] += r * P[1, :]
        R = _grad_collision_moment(Pi, alpha) - drift
        return [R[0, 0], R[1, 1], R[2, 2], R[0, 1]]
    # The Navier-Stokes guess: a* ~ sqrt(3 zeta0* nu_eta*/2), Pi_xy ~ -a*/nu_eta*.
    nu_eta, zeta0 = (3 - alpha) * (1 + alpha) / 4, 5 / 12 * (1 - alpha * alpha)
    r0 = max(math.sqrt(1.5 * zeta0 * nu_eta), 1e-3)
    x, _info, ok, message = optimize.fsolve(residual, [r0, r0 * r0 / nu_eta, 0.0, -r0 / nu_eta],
                                            xtol=1e-13, full_output=True)
    if ok != 1 or x[0] <= 0:
        raise ValueError(f"hard_sphere_usf_grad: no steady solution found ({message})")
    r, pxx, pyy, pxy = x
    T = (shear / (r * hard_sphere_nu0(1.0, gamma, C))) ** 2
    return {"T": T, "reduced_shear_rate": r,
            "xx": 1 + pxx, "yy": 1 + pyy, "zz": 1 - pxx - pyy, "xy": pxy}


def _grad_collision_moment(Pi, alpha):
    """J_ij/(p nu0) of the nonlinear Grad closure (d = 3, transport.md §2) at Pi = P/p - I."""
    PP = Pi @ Pi
    tr = np.trace(PP)
    return (-(3 - alpha) * (1 + alpha) / 4 * (Pi + (PP - tr * np.eye(3) / 3) / 14)
            - 5 / 12 * (1 - alpha * alpha) * (1 + tr / 40) * np.eye(3))


def hard_sphere_usf_grad_gaussian(alpha, reduced_shear, d=3):
    """Steady USF of hard spheres under the Gaussian thermostat (d = 3) in the nonlinear Grad
    closure [approx]: the thermostat's force xi v holds T, so the shear rate a* = a/nu0(T) is
    free; P/p balances -a* (delta_ix P_yj + delta_jx P_yi) + J_ij + 2 xi P_ij = 0 with xi from
    the trace. Returns P/p as xx, yy, zz, xy. At small a*, P_xy/p = -a*/(nu_eta* - zeta0*): the
    thermostat's viscosity, not the Navier-Stokes one (usf_viscosity)."""
    check_dimension(d, (3,), "hard_sphere_usf_grad_gaussian")
    a = float(reduced_shear)

    def balance(x):
        pxx, pyy, pxy = x
        Pi = np.array([[pxx, pxy, 0.0], [pxy, pyy, 0.0], [0.0, 0.0, -pxx - pyy]])
        P = np.eye(3) + Pi
        drift = np.zeros((3, 3))
        drift[0, :] += a * P[1, :]
        drift[:, 0] += a * P[1, :]
        J = _grad_collision_moment(Pi, alpha)
        xi2 = (np.trace(drift) - np.trace(J)) / np.trace(P)  # 2 xi: the trace stays
        R = J - drift + xi2 * P
        return [R[0, 0], R[1, 1], R[0, 1]]

    nu = (3 - alpha) * (1 + alpha) / 4 - 5 / 12 * (1 - alpha * alpha)
    x, _info, ok, message = optimize.fsolve(balance, [0.0, 0.0, -a / nu], xtol=1e-13,
                                            full_output=True)
    if ok != 1:
        raise ValueError(f"hard_sphere_usf_grad_gaussian: no steady solution found ({message})")
    pxx, pyy, pxy = x
    return {"xx": 1 + pxx, "yy": 1 + pyy, "zz": 1 - pxx - pyy, "xy": pxy}


def maxwell_drag_a2(alpha, omega, d=3):
    """a2 of Maxwell molecules (lambda = 0, d = 3, geometry uniform) under drag and white noise
    [exact] (transport.md §4): 2 (1-alpha)^2 (1+alpha)/[13 - 9 alpha + alpha^2 - alpha^3
    + 12 omega (1 - alpha)], omega = 2 gamma_d/zeta, zeta = nu (1 - alpha^2)/4."""
    check_dimension(d, (3,), "maxwell_drag_a2")
    return 2 * (1 - alpha) ** 2 * (1 + alpha) / (
        13 - 9 * alpha + alpha ** 2 - alpha ** 3 + 12 * omega * (1 - alpha))


def hard_sphere_drag_state(alpha, beta, drag, gamma, C, d=3):
    """Steady temperature and a2 of hard spheres under drag and white noise, first Sonine
    [approx] (transport.md §4): a2 = 16 (1-alpha)(1-2 alpha^2)/[73 + 56 d - 3 alpha (35 + 8d)
    + 30 alpha^2 (1-alpha) + 32 omega (d+2)(1-alpha)], omega = 2 gamma_d/zeta(T), with the
    energy balance 2 beta = (zeta(T) + 2 gamma_d) T, zeta = (16/3) sqrt(pi) gamma C (1 - alpha^2)
    sqrt(T) (1 + 3 a2/16) (d = 3), solved together. Returns (T, a2)."""
    d = check_dimension(d, (3,), "hard_sphere_drag_state")

    def zeta(T, a2):
        return 16 / 3 * math.sqrt(math.pi) * gamma * C * (1 - alpha * alpha) * math.sqrt(T) * (
            1 + 3 * a2 / 16)

    def a2_of(T, a2):
        omega = 2 * drag / zeta(T, a2)
        return 16 * (1 - alpha) * (1 - 2 * alpha * alpha) / (
            73 + 56 * d - 3 * alpha * (35 + 8 * d) + 30 * alpha * alpha * (1 - alpha)
            + 32 * omega * (d + 2) * (1 - alpha))

    def residual(x):
        T, a2 = x
        T = abs(T)
        return [(zeta(T, a2) + 2 * drag) * T - 2 * beta, a2 - a2_of(T, a2)]
    T0 = (2 * beta / (zeta(1.0, 0.0) + 2 * drag)) ** 2
    x, _info, ok, message = optimize.fsolve(residual, [max(T0, 1e-3), 0.0], xtol=1e-13,
                                            full_output=True)
    if ok != 1:
        raise ValueError(f"hard_sphere_drag_state: no steady state found ({message})")
    return abs(x[0]), x[1]
