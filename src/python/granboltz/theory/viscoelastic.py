"""Free cooling of viscoelastic hard spheres, d = 3 (Beyond the papers; the theory functions take d
and raise ValueError for another, granboltz.theory.dimension): the restitution law of the
simulator's `dsmc.restitution: {law: viscoelastic, delta: δ}`, the cooling law T(t) ~ t^(-5/3)
(Brilliantov & Pöschel); the table rows and verdict of the report item are
granboltz.reproduction.viscoelastic.

Law (Schwager & Pöschel 1998; docs/config.md, Restitution laws): ε = 1 − C1 x + C2 x², x = δ g_n^(1/5),
held at 7/12 for x ≥ X_HOLD = 5/(6 C1).  Units as granboltz.reproduction.beyond: density 1, kernel B = C|u|, collision
term γQ.  The Maxwellian moment equation is

    dT/dt = −ζ(T) T,  ζ(T) = (16/3)√π γC (n − 1)/n √T Φ(T),  Φ(T) = ⟨|u| g_n² (1 − ε²)⟩/⟨|u| g_n²⟩,

the simulator's `estimate` with 1 − α² replaced by Φ [approx: a2 = 0].  To leading order Φ = A1 δ T^(1/10),
so dT/dt ∝ −δ T^(8/5) and T = T0 [1 + (3/5) t/τ0]^(−5/3) with τ0 = 1/ζ(T0) (reference/beyond.md §6),
not Haff's t^(−2).  The local slope d ln T/d ln t tends to −5/3 only slowly: to first order

    s(t) = −(5/3) [1 − 5τ0/(3t) + (B1/5) δ T(t)^(1/10)],   B1 = A2/A1 = 1.53,

the offset τ0 and the x² term of ε, which decays like t^(−1/6) (late_slope_expansion; the tests check it
against the moment equation).  free_cooling_temperature solves the moment equation with the full law.
"""

import math

import numpy as np

from .dimension import check_dimension
from .sonine import cooling_rate


C1 = math.gamma(0.6) * math.sqrt(math.pi) / (2**0.2 * 5**0.4 * math.gamma(2.1))  # 1.1534489


C2 = 0.6 * C1**2


X_HOLD, EPS_HOLD = 5 / (6 * C1), 7 / 12  # the two-term series' minimum: ε is held there


# 1 − ε(x)² = Σ_k LOSS[k] x^k (k = 1…4) below the hold
LOSS = (0.0, 2 * C1, -(C1**2 + 2 * C2), 2 * C1 * C2, -(C2**2))


def _moment(k):
    """⟨(4 s z)^(k/10)⟩ over the pair weight |u| g_n² of a Maxwellian at T = 1: s = u²/4 ~ Gamma(3), z = (û·n)²
    with density 2z, so that x = δ (4 T s z)^(1/10)."""
    return 4 ** (k / 10) * math.gamma(3 + k / 10) / 2 * 2 / (2 + k / 10)


A1 = LOSS[1] * _moment(1)  # Φ = A1 δ T^(1/10) − A2 δ² T^(1/5) + …: A1 = 2.7731


A2 = -LOSS[2] * _moment(2)


B1 = A2 / A1


# First-Sonine factor of ⟨|u|^p⟩, p(p − 2)/16 (granboltz.theory.sonine.cooling_rate), at the loss term's p = 16/5
P_LOSS = 3.2  # the loss term's moment order p = 16/5 (not lambda_p)


KAPPA = P_LOSS * 1.2 / 16


def restitution(x):
    """ε(x), x = δ g_n^(1/5): 1 − C1 x + C2 x², held at 7/12 for x ≥ X_HOLD (as the simulator)."""
    x = np.asarray(x, dtype=float)
    return np.where(x >= X_HOLD, EPS_HOLD, 1 - x * (C1 - C2 * x))


def loss_fraction(T, delta, d=3):
    """Φ(T) = ⟨|u| g_n² (1 − ε²)⟩/⟨|u| g_n²⟩ for a Maxwellian at temperature T (the factor that replaces
    1 − α² in the cooling rate): the series in closed form, plus the correction where x ≥ X_HOLD (incomplete
    gamma functions, Gauss-Legendre in z; nil unless δ (g_n)^(1/5) reaches 0.72 in the thermal range).
    d = 3 only (the pair weight |u| g_n² of spheres)."""
    from scipy.special import gammaincc

    check_dimension(d, (3,), "viscoelastic.loss_fraction")
    if delta == 0:
        return 0.0
    scale = [(delta * T**0.1) ** k for k in range(5)]  # x^k = scale[k] (4 s z)^(k/10)
    phi = sum(LOSS[k] * scale[k] * _moment(k) for k in range(1, 5))
    q = (X_HOLD / delta) ** 10 / (4 * T)  # x >= X_HOLD where s z >= q
    if q > 700:  # the weight beyond it is below e^-700
        return float(phi)
    zg, wg = np.polynomial.legendre.leggauss(64)
    z, w = (zg + 1) / 2, wg / 2
    # where held, 1 - eps_hold^2 = (1 - eps^2) + (eps^2 - eps_hold^2), eps^2 - eps_hold^2 = sum excess[k] x^k
    excess = (1.0 - EPS_HOLD**2, -2 * C1, C1**2 + 2 * C2, -2 * C1 * C2, C2**2)
    tail = sum(excess[k] * scale[k] * 4 ** (k / 10) * math.gamma(3 + k / 10) / 2
               * np.sum(w * 2 * z ** (1 + k / 10) * gammaincc(3 + k / 10, q / z)) for k in range(5))
    return float(phi + tail)


def cooling_rate_visco(T, delta, gamma, C, n=None, d=3):
    """ζ(T) of the Maxwellian moment equation dT/dt = −ζ T: the hard-sphere rate with 1 − α² → Φ(T) (d = 3)."""
    return float(cooling_rate(T, 0.0, gamma, C, 1, n=n, d=d)) * loss_fraction(T, delta, d)


def tau0(delta, T0, gamma, C, n=None, d=3):
    """τ0 = 1/ζ(T0) to leading order in δ (ζ = (16/3)√π γC √T0 A1 δ T0^(1/10)); ∞ for δ = 0 (d = 3)."""
    check_dimension(d, (3,), "viscoelastic.tau0")
    zeta0 = float(cooling_rate(T0, 0.0, gamma, C, 1, n=n)) * A1 * delta * T0**0.1
    return math.inf if zeta0 == 0 else 1 / zeta0


def asymptotic_temperature(t, delta, T0, gamma, C, n=None, d=3):
    """T0 [1 + (3/5) t/τ0]^(−5/3), the leading order in δ [approx; exponent exact as δ T^(1/10) → 0] (d = 3)."""
    return T0 * (1 + 0.6 * np.asarray(t, dtype=float) / tau0(delta, T0, gamma, C, n, d)) ** (-5 / 3)


def free_cooling_temperature(t, delta, T0, gamma, C, n=None, d=3):
    """T(t) of the Maxwellian moment equation with the full law (DOP853 in ln T, relative tolerance 1e-11),
    at the times t (≥ 0) [approx: with a steady a2, the true T is about this T times (1 + KAPPA a2)^(−5/3) late]
    (d = 3)."""
    from scipy.integrate import solve_ivp

    check_dimension(d, (3,), "viscoelastic.free_cooling_temperature")
    t = np.asarray(t, dtype=float)
    if delta == 0 or t.max() == 0:
        return np.full(t.shape, float(T0))
    sol = solve_ivp(lambda _, y: [-cooling_rate_visco(math.exp(y[0]), delta, gamma, C, n)], (0.0, float(t.max())),
                    [math.log(T0)], method="DOP853", rtol=1e-11, atol=1e-12, dense_output=True)
    return np.exp(sol.sol(t)[0])


def local_slope(t, T, delta, gamma, C, n=None, d=3):
    """d ln T/d ln t = −t ζ(T) of the moment equation at (t, T(t)) (d = 3)."""
    check_dimension(d, (3,), "viscoelastic.local_slope")
    return np.array([-ti * cooling_rate_visco(Ti, delta, gamma, C, n, d) for ti, Ti in zip(np.atleast_1d(t), np.atleast_1d(T))])


def late_slope_expansion(t, T, delta, tau, d=3):
    """First-order local slope −(5/3)[1 − 5τ0/(3t) + (B1/5) δ T^(1/10)] for t ≫ τ0 (module docstring; d = 3)."""
    check_dimension(d, (3,), "viscoelastic.late_slope_expansion")
    t, T = np.asarray(t, dtype=float), np.asarray(T, dtype=float)
    return -5 / 3 * (1 - 5 * tau / (3 * t) + B1 / 5 * delta * T**0.1)
