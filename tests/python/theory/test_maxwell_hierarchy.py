"""Tests of granboltz.theory.maxwell_hierarchy: the exact moment hierarchy of GRW05 eqs. 3-4 for Maxwell
pseudomolecules against an independent expansion, a direct Monte Carlo of E|v'|^2p, GRW05 eq. 16,
the steady moments and Crit(t) of ../shared/reference/tails.md, and numerical ODE solutions."""

from fractions import Fraction as F
from math import comb

import numpy as np
import pytest
import sympy
from scipy.integrate import solve_ivp

from granboltz.theory import maxwell_hierarchy as mh

# tails.md: steady moments, GRW05 Ex. 7 (alpha = 1/10, beta = 30, nu = 16) and RW05 §4 (1/2, 1, 4)
EX7 = [F(500, 11), F(17363750000, 4395567), 5.512305e5, 1.130143e8, 3.215805e10, 1.218281e13,
       5.948159e15, 3.645382e18]
RW05 = [F(8), F(8000, 69), F(332864000, 129789), 7.970707e4, 3.313283e6, 1.781569e8, 1.208551e10,
        1.013665e12]
CRIT = [0.08116, 0.10151, 0.11076, 0.11513, 0.11721, 0.11819, 0.11865, 0.11887]


def direct_coefficients(p, alpha):
    """E|v'|^2p by expanding |v'|^2 = X + Y mu in x = |v|^2, y = |w|^2, z = v.w (the module
    docstring's first route), then E[x^m y^n z^l] = M_{2m+l} M_{2n+l} / (l + 1), l even."""
    x, y, z = sympy.symbols("x y z")
    al = sympy.Rational(alpha.numerator, alpha.denominator)
    a, b = (3 - al) / 4, (1 + al) / 4
    A2, U2 = a**2 * x + b**2 * y + 2 * a * b * z, x + y - 2 * z
    X, Y2 = A2 + b**2 * U2, 4 * b**2 * U2 * A2
    poly = sympy.Poly(sum(comb(p, 2 * i) * X ** (p - 2 * i) * Y2**i / (2 * i + 1) for i in range(p // 2 + 1)),
                      x, y, z)
    c = [F(0)] * (p + 1)
    for (m, n, l), coeff in poly.terms():
        if l % 2 == 0:
            c[m + l // 2] += F(int(coeff.p), int(coeff.q)) / (l + 1)
    return c


@pytest.mark.parametrize("alpha", [F(1, 10), F(1, 2), F(1)])
def test_fourier_coefficients_equal_the_direct_expansion(alpha):
    for p in range(1, 7):
        assert list(mh.collision_coefficients(p, alpha)) == direct_coefficients(p, alpha)


def sample_post_collision(rng, n, radius, alpha):
    """v' of GRW05 eq. 4 for v, w independent isotropic with |v| drawn by `radius`, e uniform."""
    def iso(r):
        d = rng.normal(size=(n, 3))
        return r[:, None] * d / np.linalg.norm(d, axis=1)[:, None]
    v, w, e = iso(radius(n)), iso(radius(n)), iso(np.ones(n))
    u = v - w
    return 0.5 * (v + w) + (1 - alpha) / 4 * u + (1 + alpha) / 4 * np.linalg.norm(u, axis=1)[:, None] * e


@pytest.mark.parametrize("name", ["maxwellian", "exponential"])
def test_coefficients_match_a_direct_monte_carlo_of_the_collision_map(name):
    rng = np.random.default_rng(20051)
    alpha = F(3, 10)
    if name == "maxwellian":  # T = 1: M_2q = (2q+1)!!
        radius = lambda n: np.linalg.norm(rng.normal(size=(n, 3)), axis=1)  # noqa: E731
        M = [float(m) for m in mh.maxwellian_moments(4, 1)]
    else:  # density ~ exp(-|v|): |v| ~ Gamma(3), M_2q = (2q+2)!/2
        radius = lambda n: rng.gamma(3.0, size=n)  # noqa: E731
        M = [float(np.prod(np.arange(1, 2 * q + 3))) / 2 for q in range(5)]
    n = 2_000_000
    s2 = np.sum(sample_post_collision(rng, n, radius, float(alpha)) ** 2, axis=1)
    for p in range(1, 5):
        c = mh.collision_coefficients(p, alpha)
        exact = sum(float(c[q]) * M[q] * M[p - q] for q in range(p + 1))
        sample = s2**p
        half_width = 3.2 * sample.std() / np.sqrt(n)  # lambda_p = 3.2 as in the simulations
        assert abs(sample.mean() - exact) < half_width, (p, sample.mean(), exact, half_width)


def test_p1_is_grw05_eq16():
    for alpha in (F(1, 10), F(1, 2), F(9, 10)):
        c = mh.collision_coefficients(1, alpha)
        assert c[0] + c[1] == (3 + alpha**2) / 4
        # dT/dt = 2 beta - gamma pi C0 (1 - alpha^2) T, nu = 4 pi C0 gamma; T_inf of eq. 17
        nu, beta = F(16), F(30)
        assert mh.steady_moments(1, alpha, beta, nu)[1] / 3 == 2 * beta / (nu / 4 * (1 - alpha**2))
    t = np.linspace(0, 8, 17)  # RW05 eq. 28 (GRW05 Ex. 3): T = e^{-3t/4} + 8/3 (1 - e^{-3t/4})
    M = mh.time_dependent_moments(1, F(1, 2), 1, mh.collision_rate(4, F(1, 4)))
    assert np.allclose(mh.evaluate(M[1], t) / 3, np.exp(-0.75 * t) + 8 / 3 * (1 - np.exp(-0.75 * t)), rtol=1e-14)


def test_fourth_moment_equation_of_rw05():
    c = mh.collision_coefficients(2, F(1, 2))
    assert c[1] == F(45, 128) and 1 - c[0] - c[2] == F(69, 128)


@pytest.mark.parametrize("params,table", [((F(1, 10), 30, mh.collision_rate(16, F(1, 4))), EX7),
                                          ((F(1, 2), 1, mh.collision_rate(1, 1)), RW05)])
def test_steady_moments_match_the_reference_table(params, table):
    M = mh.steady_moments(8, *params)
    for p, ref in enumerate(table, start=1):
        if isinstance(ref, F):
            assert M[p] == ref
        else:
            assert float(M[p]) == pytest.approx(ref, rel=1e-6)


def test_crit_of_rw05_matches_the_reference_values():
    got = mh.crit_exact(np.arange(1, 9), F(1, 2), 1, 4)
    assert np.allclose(got, CRIT, atol=5e-6)
    assert mh.crit_steady(F(1, 2), 1, 4) == pytest.approx(0.11907, abs=5e-6)
    assert mh.crit_exact(np.array([0.0]), F(1, 2), 1, 4)[0] == pytest.approx(0, abs=1e-12)


def closed_system(pmax, alpha, beta, nu):
    """The right-hand side of the hierarchy in floats, written out from its definition."""
    c = [[float(x) for x in mh.collision_coefficients(p, alpha)] for p in range(pmax + 1)]

    def rhs(_, m):
        M = np.concatenate([[1.0], m])
        return [2 * p * (2 * p + 1) * beta * M[p - 1]
                + nu * (sum(c[p][q] * M[q] * M[p - q] for q in range(p + 1)) - M[p]) for p in range(1, pmax + 1)]
    return rhs


def test_time_dependent_moments_match_a_numerical_solution_and_relax_to_the_steady_ones():
    alpha, beta, nu, T0, pmax = F(1, 10), F(30), F(16), F(1), 6
    exact = mh.time_dependent_moments(pmax, alpha, beta, nu, T0)
    t = np.linspace(0, 2.5, 11)
    m0 = [float(m) for m in mh.maxwellian_moments(pmax, T0)[1:]]
    sol = solve_ivp(closed_system(pmax, alpha, float(beta), float(nu)), (0, 2.5), m0, t_eval=t,
                    method="DOP853", rtol=1e-12, atol=0)
    for p in range(1, pmax + 1):
        assert np.allclose(mh.evaluate(exact[p], t), sol.y[p - 1], rtol=1e-8)
    steady = mh.steady_moments(pmax, alpha, beta, nu)
    for p in range(1, pmax + 1):
        assert mh.evaluate(exact[p], [60.0])[0] == pytest.approx(float(steady[p]), rel=1e-10)


def test_steady_a2_closed_form():
    for alpha in (F(1, 10), F(1, 3), F(1, 2), F(4, 5), F(99, 100)):
        M = mh.steady_moments(2, alpha, F(7, 3), F(5))
        assert mh.sonine_a2(M[1], M[2]) == mh.steady_a2_formula(alpha)
    assert float(mh.steady_a2_formula(F(1, 2))) == pytest.approx(0.0870, abs=5e-5)
    assert float(mh.steady_a2_formula(F(1, 10))) == pytest.approx(0.1472, abs=5e-5)


def test_hcs_scaled_moments_are_the_long_time_limit_of_free_cooling():
    alpha, pmax = F(1, 2), 4
    m = mh.hcs_scaled_moments(pmax, alpha)
    assert m[1] == 3 and mh.hcs_a2(alpha) == m[2] / 15 - 1
    # free cooling in scaled variables m_p = M_2p / T^p: with beta = 0 the right-hand side is
    # homogeneous of degree p, so dm_p/dt = rhs_p(m) - p m_p rhs_1(m) / m_1
    rhs = closed_system(pmax, alpha, 0.0, 1.0)

    def scaled(t, m):
        d = rhs(t, m)
        return [d[p - 1] - p * m[p - 1] * d[0] / m[0] for p in range(1, pmax + 1)]
    m0 = [float(x) for x in mh.maxwellian_moments(pmax, 1)[1:]]
    sol = solve_ivp(scaled, (0, 3000), m0, method="DOP853", rtol=1e-12, atol=0)
    for p in range(1, pmax + 1):
        assert sol.y[p - 1, -1] == pytest.approx(float(m[p]), rel=1e-9)
    with pytest.raises(ValueError, match="diverges"):
        mh.hcs_scaled_moments(5, alpha)
    with pytest.raises(ValueError, match="diverges"):
        mh.hcs_scaled_moments(3, F(1, 10))
