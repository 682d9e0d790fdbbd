r"""Exact moment hierarchy of the heated inelastic Boltzmann equation, Maxwell pseudomolecules, d = 3
(every function takes d and raises ValueError for another: granboltz.theory.dimension).

Equation (GRW05 eq. 1): f_t - beta Lap_v f = gamma Q_alpha(f), kernel B = C0 (lambda = 0, eq. 7),
density 1, bulk velocity 0.  M_2p = <|v|^2p>, nu = 4 pi C0 gamma (the collision rate).

Derivation.  In the weak form (eq. 3) take phi = |v|^2p.  With B = C0 the e-integral is 4 pi C0
times the mean over e uniform on S^2; swapping v <-> w and e -> -e maps w' onto v' (eq. 4), so the
two gain terms are equal and gamma <Q, phi> = nu (E|v'|^2p - M_2p), with v, w independent draws
of f.  Green's formula gives beta <Lap f, phi> = beta <f, Lap phi> = 2p(2p+1) beta M_{2p-2}:

    dM_2p/dt = 2p(2p+1) beta M_{2p-2} + nu (E|v'|^2p - M_2p).

Eq. 4 reads v' = A + b|u| e with A = a v + b w, a = (3 - alpha)/4, b = (1 + alpha)/4, u = v - w.
So |v'|^2 = X + Y mu with X = |A|^2 + b^2 |u|^2, Y = 2 b |u| |A|, mu = (A.e)/|A| uniform on
[-1, 1]: E_e |v'|^2p = sum_{k even} C(p, k) X^{p-k} Y^k / (k + 1), a polynomial in x = |v|^2,
y = |w|^2, z = v.w (Y^k = (4 b^2 |u|^2 |A|^2)^{k/2}).  For independent isotropic v, w,
E[x^m y^n z^l] = M_{2m+l} M_{2n+l} / (l + 1) for l even, 0 for l odd (E cos^l = 1/(l + 1)).  Hence

    E|v'|^2p = sum_{q=0}^{p} c_q M_2q M_{2(p-q)},   c_q rational in alpha (collision_coefficients),

and the hierarchy closes and is triangular: with r_p = nu (1 - c_0 - c_p) (M_0 = 1),
    dM_2p/dt = -r_p M_2p + 2p(2p+1) beta M_{2p-2} + nu sum_{0<q<p} c_q M_2q M_{2(p-q)}.
The c_q are computed in Fourier space (Bobylev's trick; the x, y, z expansion above is the
independent check in the tests): E_e exp(-i k.v') = E_n exp(-i k+.v - i k-.w) with
k+ = a k + b|k| n, k- = (1 - a) k - b|k| n (|u| k.e and |k| u.n have the same law), and for
isotropic f, E (k.v)^2p = |k|^2p M_2p / (2p + 1); matching the |k|^2p terms (|k| = 1, mu = k.n):
    c_q = (2p+1)! / ((2q+1)! (2p-2q+1)!) * E_mu[|k+|^2q |k-|^2(p-q)],
    |k+|^2 = a^2 + b^2 + 2ab mu,  |k-|^2 = (1-a)^2 + b^2 - 2(1-a)b mu.
p = 1 gives c_0 + c_1 = (3 + alpha^2)/4, i.e. dT/dt = 2 beta - gamma pi C0 (1 - alpha^2) T (eq. 16).
Solved exactly: steady moments as Fractions, time-dependent ones as sums of t^k e^{-rate t} with
rational coefficients (each equation is linear in its own moment, forced by lower ones).
"""
from fractions import Fraction
from functools import lru_cache
from math import factorial, prod, sqrt

import mpmath
import numpy as np

from .dimension import check_dimension


def rational(x):
    """x as a Fraction (ints, Fractions and decimal strings exactly; floats by their binary value)."""
    return x if isinstance(x, Fraction) else Fraction(x)


def collision_rate(gamma, pi_c0, d=3):
    """nu = 4 pi C0 gamma, given gamma and pi*C0 (1/4 for C0 = 1/(4 pi), 1 for C0 = 1/pi)."""
    check_dimension(d, (3,), "maxwell_hierarchy.collision_rate")
    return 4 * rational(gamma) * rational(pi_c0)


@lru_cache(maxsize=None)
def _coefficient_table(pmax, alpha):
    # Fourier route (module docstring): c_q = (2p+1)!/((2q+1)!(2p-2q+1)!) * (1/2) int_{-1}^{1}
    # (a^2 + b^2 + 2ab mu)^q ((1-a)^2 + b^2 - 2(1-a)b mu)^(p-q) dmu, polynomials in mu.
    a, b = (3 - alpha) / 4, (1 + alpha) / 4
    scale = 16 * alpha.denominator**2  # integer arithmetic inside the convolutions (speed)
    kp = np.array([int((a * a + b * b) * scale), int(2 * a * b * scale)], dtype=object)
    km = np.array([int(((1 - a) ** 2 + b * b) * scale), int(-2 * (1 - a) * b * scale)], dtype=object)
    pp, pm = [np.array([1], dtype=object)], [np.array([1], dtype=object)]
    for _ in range(pmax):
        pp.append(np.convolve(pp[-1], kp))
        pm.append(np.convolve(pm[-1], km))
    odd_fact = [factorial(2 * q + 1) for q in range(pmax + 1)]
    table = []
    for p in range(pmax + 1):
        c = []
        for q in range(p + 1):
            poly = np.convolve(pp[q], pm[p - q])
            mean = sum(Fraction(int(poly[j]), j + 1) for j in range(0, len(poly), 2))
            c.append(Fraction(odd_fact[p], odd_fact[q] * odd_fact[p - q] * scale**p) * mean)
        table.append(tuple(c))
    return tuple(table)


def collision_coefficients(p, alpha, d=3):
    """(c_0, ..., c_p), Fractions: E|v'|^2p = sum_q c_q M_2q M_2(p-q) for v' of GRW05 eq. 4 with
    e uniform on S^2 and v, w independent isotropic velocities (module docstring)."""
    check_dimension(d, (3,), "maxwell_hierarchy.collision_coefficients")
    return _coefficient_table(int(p), rational(alpha))[int(p)]


def _decay_rates(pmax, alpha, nu):
    return [nu * (1 - c[0] - c[-1]) for c in _coefficient_table(pmax, alpha)]


def _forcing_terms(p, alpha, beta, nu):
    """(coefficient, (i, j)) pairs of the forcing of M_2p: 2p(2p+1) beta M_{2p-2} M_0 + ..."""
    c = collision_coefficients(p, alpha)
    terms = [(2 * p * (2 * p + 1) * beta, (p - 1, 0))]
    terms += [(nu * c[q], (q, p - q)) for q in range(1, p)]
    return terms


def steady_moments(pmax, alpha, beta, nu, d=3):
    """Exact steady moments [M_0 = 1, M_2, ..., M_2pmax] (Fractions) of the heated equation."""
    check_dimension(d, (3,), "maxwell_hierarchy.steady_moments")
    alpha, beta, nu = rational(alpha), rational(beta), rational(nu)
    rates, M = _decay_rates(pmax, alpha, nu), [Fraction(1)]
    for p in range(1, pmax + 1):
        M.append(sum(k * M[i] * M[j] for k, (i, j) in _forcing_terms(p, alpha, beta, nu)) / rates[p])
    return M


def maxwellian_moments(pmax, T0, d=3):
    """<|v|^2p> = (2p+1)!! T0^p of the Maxwellian of temperature T0 (GRW05 eq. 33), p = 0..pmax."""
    check_dimension(d, (3,), "maxwell_hierarchy.maxwellian_moments")
    T0 = rational(T0)
    return [prod(range(1, 2 * p + 2, 2)) * T0**p for p in range(pmax + 1)]


# An exponential polynomial: {rate: [a_0, a_1, ...]} meaning sum_rate sum_k a_k t^k e^{-rate t}.
def _mul(f, g):
    out = {}
    for r1, p1 in f.items():
        for r2, p2 in g.items():
            acc = out.setdefault(r1 + r2, [Fraction(0)] * (len(p1) + len(p2) - 1))
            if len(acc) < len(p1) + len(p2) - 1:
                acc.extend([Fraction(0)] * (len(p1) + len(p2) - 1 - len(acc)))
            for i, a in enumerate(p1):
                for j, b in enumerate(p2):
                    acc[i + j] += a * b
    return out


def _add(f, g, scale=1):
    out = {r: list(p) for r, p in f.items()}
    for r, p in g.items():
        acc = out.setdefault(r, [])
        acc.extend([Fraction(0)] * (len(p) - len(acc)))
        for k, a in enumerate(p):
            acc[k] += scale * a
    return out


def _solve_linear(rate, forcing, y0):
    """Exact solution of y' = -rate y + forcing(t), y(0) = y0 (Duhamel, term by term)."""
    out = {rate: [Fraction(y0)]}
    for mu, poly in forcing.items():
        for k, a in enumerate(poly):
            if a == 0:
                continue
            if mu == rate:  # resonance: int_0^t s^k ds
                out = _add(out, {rate: [Fraction(0)] * (k + 1) + [a / (k + 1)]})
                continue
            d = rate - mu  # P' + d P = t^k  =>  P = sum_j (-1)^j k!/(k-j)! t^(k-j) / d^(j+1)
            P = [Fraction(0)] * (k + 1)
            for j in range(k + 1):
                P[k - j] = (-1) ** j * Fraction(prod(range(k - j + 1, k + 1))) / d ** (j + 1)
            out = _add(out, {mu: [a * c for c in P], rate: [-a * P[0]]})
    return out


def time_dependent_moments(pmax, alpha, beta, nu, T0=1, d=3):
    """Exact M_2p(t), p = 0..pmax, from a Maxwellian of temperature T0: a list of exponential
    polynomials {rate: [a_0, a_1, ...]} = sum a_k t^k e^{-rate t}; evaluate with `evaluate`.
    The number of rates grows like the partitions of p: pmax = 8 takes 0.2 s, 12 takes 4 s."""
    check_dimension(d, (3,), "maxwell_hierarchy.time_dependent_moments")
    alpha, beta, nu = rational(alpha), rational(beta), rational(nu)
    rates, init = _decay_rates(pmax, alpha, nu), maxwellian_moments(pmax, T0)
    M = [{Fraction(0): [Fraction(1)]}]
    for p in range(1, pmax + 1):
        forcing = {}
        for k, (i, j) in _forcing_terms(p, alpha, beta, nu):
            forcing = _add(forcing, _mul(M[i], M[j]), k)
        M.append(_solve_linear(rates[p], forcing, init[p]))
    return M


def evaluate(expoly, t, digits=80):
    """Value of an exponential polynomial (from time_dependent_moments) at times t (array).
    Summed in `digits`-digit arithmetic (mpmath): close decay rates give large terms that cancel,
    5e12-fold for M_12 and 7e42-fold for M_32 of GRW05 Ex. 7 at t = 0."""
    t = np.atleast_1d(np.asarray(t, dtype=float))
    with mpmath.workdps(digits):
        terms = [(mpmath.mpf(r.numerator) / r.denominator,
                  [mpmath.mpf(a.numerator) / a.denominator for a in poly]) for r, poly in expoly.items()]
        return np.array([float(sum(mpmath.polyval(poly[::-1], mpmath.mpf(x)) * mpmath.exp(-r * mpmath.mpf(x))
                                   for r, poly in terms)) for x in t])


def sonine_a2(M2, M4, d=3):
    """Sonine coefficient a2 = M_4/(15 T^2) - 1 with T = M_2/3 (exact for Fractions)."""
    check_dimension(d, (3,), "maxwell_hierarchy.sonine_a2")
    return 3 * M4 / (5 * M2 * M2) - 1


def steady_a2_formula(alpha, d=3):
    """Closed form of the steady a2 for lambda = 0: 2(1-alpha)^2(1+alpha)/(13-9alpha+alpha^2-alpha^3)
    (independent of beta, nu; equals sonine_a2 of steady_moments)."""
    check_dimension(d, (3,), "maxwell_hierarchy.steady_a2_formula")
    a = rational(alpha)
    return 2 * (1 - a) ** 2 * (1 + a) / (13 - 9 * a + a**2 - a**3)


def crit(M2, M4, d=3):
    """RW05 eq. 29 for an isotropic state with V = 0 (P = pI and q = 0, only the fourth-moment term
    survives): Crit = |M_4 - 15 T^2| / (sqrt(120) T^2), T = M_2/3. Arrays or floats."""
    check_dimension(d, (3,), "maxwell_hierarchy.crit")
    T = np.asarray(M2, dtype=float) / 3.0
    return np.abs(np.asarray(M4, dtype=float) - 15.0 * T**2) / (sqrt(120.0) * T**2)


def crit_exact(t, alpha, beta, nu, T0=1, d=3):
    """Exact Crit(t) of the heated Maxwell gas started from a Maxwellian of temperature T0."""
    check_dimension(d, (3,), "maxwell_hierarchy.crit_exact")
    M = time_dependent_moments(2, alpha, beta, nu, T0)
    return crit(evaluate(M[1], t), evaluate(M[2], t))


def crit_steady(alpha, beta, nu, d=3):
    """Exact steady Crit(inf) = |a2| * 15/sqrt(120) (a float)."""
    check_dimension(d, (3,), "maxwell_hierarchy.crit_steady")
    M = steady_moments(2, alpha, beta, nu)
    return float(crit(float(M[1]), float(M[2])))


def hcs_scaled_moments(pmax, alpha, d=3):
    """Moments m_p = lim M_2p(t)/T(t)^p (Fractions, m_0 = 1, m_1 = 3) of the homogeneous cooling
    state (beta = 0; independent of nu and of the initial state).  T decays like e^{-r_1 t}, so
    dm_p/dt = -(r_p - p r_1) m_p + nu sum_{0<q<p} c_q m_q m_{p-q}, so m_p tends to its fixed point
    only while r_p > p r_1; beyond that p the scaled moment grows without bound (power-law HCS
    tail) and a ValueError is raised."""
    check_dimension(d, (3,), "maxwell_hierarchy.hcs_scaled_moments")
    alpha = rational(alpha)
    rates, m = _decay_rates(pmax, alpha, Fraction(1)), [Fraction(1)]
    for p in range(1, pmax + 1):
        gap = rates[p] - p * rates[1]
        if p > 1 and gap <= 0:
            raise ValueError(f"HCS moment p = {p} diverges at alpha = {alpha} (r_p - p r_1 = {gap})")
        c = collision_coefficients(p, alpha)
        m.append(Fraction(3) if p == 1 else sum(c[q] * m[q] * m[p - q] for q in range(1, p)) / gap)
    return m


def hcs_a2(alpha, d=3):
    """Sonine coefficient a2 = m_2/15 - 1 of the Maxwell homogeneous cooling state (exact)."""
    check_dimension(d, (3,), "maxwell_hierarchy.hcs_a2")
    m = hcs_scaled_moments(2, alpha)
    return m[2] / 15 - 1
