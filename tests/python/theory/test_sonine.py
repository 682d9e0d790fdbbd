"""granboltz.theory.sonine against the numbers of reference/beyond.md (§1 table, §2 values and α_c), the
exact Maxwell hierarchy, quadrature of the Sonine-corrected cooling rate, and GRW05 eq. (17)."""

import math
from fractions import Fraction

import numpy as np
import pytest
from scipy import integrate, special

from granboltz.theory import maxwell_hierarchy as mh
from granboltz.theory import sonine
from granboltz.theory import scheme_steady_temperature

ALPHAS = [0.0, 0.2, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9]
# beyond.md §1, one list per column of its table (d = 3 hard spheres), and the d = 2 vNE lines
TABLE = {
    "hcs_vne": [0.19753, 0.14990, 0.08469, 0.05246, 0.02386, 0.00131, -0.01258, -0.01456],
    "hcs_a2_2nd": [0.12114, 0.10404, 0.06851, 0.04499, 0.02077, -0.00038, -0.01408, -0.01566],
    "hcs_a3_2nd": [-0.12958, -0.08685, -0.03535, -0.01768, -0.00796, -0.00478, -0.00473, -0.00387],
    "wn_vne": [0.06639, 0.05701, 0.03772, 0.02560, 0.01288, 0.00079, -0.00868, -0.01179],
    "wn_a2_2nd": [0.06476, 0.05560, 0.03682, 0.02492, 0.01230, 0.00018, -0.00938, -0.01246],
    "wn_a3_2nd": [-0.00823, -0.00700, -0.00439, -0.00332, -0.00278, -0.00284, -0.00321, -0.00291],
    "hcs_vne_d2": [0.28070, 0.22236, 0.13087, 0.08290, 0.03869, 0.00219, -0.02194, -0.02686],
    "wn_vne_d2": [0.08649, 0.07580, 0.05153, 0.03563, 0.01838, 0.00117, -0.01349, -0.01995],
}
COLUMNS = {
    "hcs_vne": lambda a: sonine.first_sonine_a2(a, "gaussian", 1),
    "hcs_a2_2nd": lambda a: sonine.second_sonine(a, "hcs")[0],
    "hcs_a3_2nd": lambda a: sonine.second_sonine(a, "hcs")[1],
    "wn_vne": lambda a: sonine.first_sonine_a2(a, "white_noise", 1),
    "wn_a2_2nd": lambda a: sonine.second_sonine(a)[0],
    "wn_a3_2nd": lambda a: sonine.second_sonine(a)[1],
    "hcs_vne_d2": lambda a: sonine.first_sonine_a2(a, "hcs", 1, d=2),
    "wn_vne_d2": lambda a: sonine.first_sonine_a2(a, "white_noise", 1, d=2),
}


@pytest.mark.parametrize("column", TABLE)
def test_each_column_of_the_beyond_table_to_the_digits_given(column):
    got = COLUMNS[column](np.array(ALPHAS))
    assert np.all(np.abs(got - np.array(TABLE[column])) <= 5e-6 + 1e-12), (column, got)


def test_general_lambda_first_sonine_is_vne_at_one_and_exact_at_zero():
    a = np.linspace(0, 1, 21)
    for th in ("hcs", "white_noise"):
        assert np.allclose(sonine.first_sonine_a2(a, th, 0), sonine.maxwell_a2(a, th), rtol=1e-13, atol=1e-15)
    assert np.allclose(sonine.first_sonine_a2(a, "hcs", 1), 16 * (1 - a) * (1 - 2 * a**2) / (81 - 17 * a + 30 * a**2 * (1 - a)))
    with pytest.raises(ValueError):
        sonine.first_sonine_a2(0.5, "hcs", 0, d=2)
    with pytest.raises(ValueError):
        sonine.first_sonine_a2(0.5, "heated")


def test_exact_maxwell_values_of_beyond_section_2():
    assert sonine.maxwell_a3([0.5, 0.6, 0.8], "hcs") == pytest.approx([-0.72547, -0.22209, -0.01182], abs=5e-6)
    assert sonine.maxwell_a3([0.5, 0.8], "white_noise") == pytest.approx([-0.02718, -0.00298], abs=5e-6)
    assert np.isnan(sonine.maxwell_a3(0.25, "hcs")) and np.isfinite(sonine.maxwell_a3(0.0, "white_noise"))


def _exact_a2_a3(M2, M4, M6):  # beyond.md's identities in exact arithmetic (a3 cancels 1e5-fold)
    a2 = Fraction(3, 5) * M4 / M2**2 - 1
    return a2, 1 + 3 * a2 - Fraction(9, 35) * M6 / M2**3


@pytest.mark.parametrize("alpha", ["0.3", "0.5", "0.6", "0.75", "0.9", "0.99"])
def test_exact_maxwell_a2_a3_equal_the_moment_hierarchy(alpha):
    a = Fraction(alpha)
    M = mh.steady_moments(3, a, Fraction(1), Fraction(1, 2))  # beta, nu do not matter
    m = mh.hcs_scaled_moments(3, a)
    for th, moments in (("white_noise", M[1:4]), ("hcs", m[1:4])):
        exact = [float(x) for x in _exact_a2_a3(*moments)]
        assert exact == pytest.approx([float(sonine.maxwell_a2(float(a), th)), float(sonine.maxwell_a3(float(a), th))], rel=1e-12)
        floats = sonine.sonine_from_moments(*(float(x) for x in moments))
        assert floats == pytest.approx(exact, rel=1e-9, abs=1e-12)


def test_hcs_moment_thresholds_are_those_of_beyond_and_the_pole_of_a3():
    got = [sonine.hcs_moment_threshold(p) for p in (2, 3, 4, 5, 6)]
    assert got[0] == 0.0
    assert got[1] == pytest.approx(0.270111, abs=5e-7)
    assert got[2:] == pytest.approx([0.4823, 0.5940, 0.6647], abs=5e-5)
    a = got[1]
    assert abs(11 - 46 * a + 20 * a**2 - 2 * a**3 + a**4) < 1e-10  # the denominator of a3
    for p, ac in zip((3, 4), got[1:3]):  # the hierarchy itself: finite just above, infinite just below
        mh.hcs_scaled_moments(p, ac + 1e-6)
        with pytest.raises(ValueError):
            mh.hcs_scaled_moments(p, ac - 1e-6)


@pytest.mark.parametrize("p", [2.5, 3.0, 4.0, 5.0])
def test_sonine_correction_of_the_relative_speed_moment_by_quadrature(p):
    # T = 1/2, so c = v: d/da2 E|v - w|^p = 2 E_M[|v - w|^p S2(|v|^2)], E_w by the noncentral chi moment
    def integrand(r):
        Ew = special.gamma((3 + p) / 2) / special.gamma(1.5) * special.hyp1f1(-p / 2, 1.5, -r * r)
        return 4 / math.sqrt(math.pi) * r * r * math.exp(-r * r) * Ew * (r**4 / 2 - 5 * r * r / 2 + 15 / 8)
    slope = 2 * integrate.quad(integrand, 0, np.inf, epsabs=1e-13)[0]
    maxwell = 2 ** (p / 2) * special.gamma((3 + p) / 2) / special.gamma(1.5)
    assert slope / maxwell == pytest.approx(p * (p - 2) / 16, abs=1e-9)
    lam = p - 2  # what cooling_rate uses
    ratio = sonine.cooling_rate(1.0, 0.5, 1, 1, lam, a2=0.1) / sonine.cooling_rate(1.0, 0.5, 1, 1, lam)
    assert ratio == pytest.approx(1 + 0.1 * p * (p - 2) / 16, rel=1e-14)


def test_cooling_rates_and_steady_temperatures_in_the_codes_conventions():
    C = 1 / (4 * math.pi)
    assert sonine.cooling_rate(2.0, 0.5, 4.0, C, 0) == pytest.approx(0.75)  # GRW05 eq. 16, k = gamma pi C (1 - a^2)
    K = 16 / 3 * math.sqrt(math.pi) * 2.0 * C * (1 - 0.8**2)
    assert sonine.cooling_rate(4.0, 0.8, 2.0, C, 1) == pytest.approx(K * 2.0, rel=1e-14)
    assert sonine.cooling_rate(4.0, 0.8, 2.0, C, 1, n=64) == pytest.approx(K * 2.0 * 63 / 64, rel=1e-14)
    for a in (0.2, 0.5, 0.9):
        assert sonine.maxwell_steady_temperature(a, 1.0, 4.0, C) == pytest.approx(
            scheme_steady_temperature("nosplit", 0.1, a, 1.0, 4.0, C), rel=1e-14)
        T = sonine.hard_sphere_steady_temperature(a, 1.0, 4.0, C)
        a2 = sonine.first_sonine_a2(a)
        assert 2.0 == pytest.approx(K / (2.0 * (1 - 0.8**2)) * 4.0 * (1 - a * a) * (1 + 3 * a2 / 16) * T**1.5, rel=1e-13)
        T0 = sonine.hard_sphere_steady_temperature(a, 1.0, 4.0, C, sonine=False)
        assert T / T0 == pytest.approx((1 + 3 * a2 / 16) ** (-2 / 3), rel=1e-14)


# d = 2 second Sonine (hard disks): derived with tests/sonine_moments.py; its output at these alpha
# (six digits), and the values tests/test_dimension.cpp quotes (white noise 0.5, HCS 0.8, 0.9)
D2_SECOND = {  # alpha: (HCS a2, HCS a3, white-noise a2, white-noise a3)
    0.3: (0.113016, -0.119371, 0.063128, -0.010027),
    0.5: (0.065454, -0.037106, 0.034524, -0.005496),
    0.8: (-0.025507, -0.010357, -0.014769, -0.006057),
    0.9: (-0.029671, -0.009366, -0.021316, -0.006141),
}


@pytest.mark.parametrize("alpha", sorted(D2_SECOND))
def test_second_sonine_of_hard_disks_is_the_derivation_output(alpha):
    h2, h3, w2, w3 = D2_SECOND[alpha]
    assert sonine.second_sonine(alpha, "hcs", d=2) == pytest.approx((h2, h3), abs=6e-7)
    assert sonine.second_sonine(alpha, "white_noise", d=2) == pytest.approx((w2, w3), abs=6e-7)


def test_second_sonine_of_hard_disks_vanishes_when_elastic_and_refuses_other_d():
    for th in ("hcs", "white_noise"):
        assert sonine.second_sonine(1.0, th, d=2) == (0.0, 0.0)
    with pytest.raises(ValueError):
        sonine.second_sonine(0.5, "hcs", d=4)
    # the d = 3 default is unchanged
    assert sonine.second_sonine(0.5, "hcs") == sonine.second_sonine(0.5, "hcs", d=3)


def _disk_collision_moments(alpha):
    """J[p, k] = E_{c1, c2 ~ M}[|u| w_k <c1'^2p + c2'^2p - c1^2p - c2^2p>_n] of hard disks (d = 2, M ~
    exp(-c^2), impact angle density cos/2) with w_0 = 1, w_k = L_k(c1^2) + L_k(c2^2) (Laguerre,
    d/2 - 1 = 0), by Gauss quadrature: the centre of mass G ~ N(0, 1/4) per component (Hermite:
    the integrand is a polynomial in G, so exact), u = (r, 0) by isotropy with r ~ r e^(-r^2/2)
    (Legendre on (0, 16)), the impact angle by Legendre (a smooth integrand): another method than
    the symbolic algebra of tests/sonine_moments.py."""
    x, wx = np.polynomial.hermite_e.hermegauss(8)
    x, wx = x / 2, wx / math.sqrt(2 * math.pi)
    r, wr = np.polynomial.legendre.leggauss(120)
    r, wr = 8 * (r + 1), 8 * wr
    wr = wr * r * np.exp(-r * r / 2)
    th, wt = np.polynomial.legendre.leggauss(40)
    th, wt = th * math.pi / 2, wt * math.pi / 2
    wt = wt * np.cos(th) / 2
    G1, G2, R, TH = np.meshgrid(x, x, r, th, indexing="ij")
    W = np.einsum("i,j,k,l->ijkl", wx, wx, wr, wt)
    c, s = np.cos(TH), np.sin(TH)
    k = (1 + alpha) / 2 * R * c  # (1 + alpha)/2 (u.n): v' = v - k n, w' = w + k n
    x1, x2 = (G1 + R / 2) ** 2 + G2**2, (G1 - R / 2) ** 2 + G2**2
    y1, y2 = (G1 + R / 2 - k * c) ** 2 + (G2 - k * s) ** 2, (G1 - R / 2 + k * c) ** 2 + (G2 + k * s) ** 2
    weight = {0: 1.0, 2: (1 - 2 * x1 + x1**2 / 2) + (1 - 2 * x2 + x2**2 / 2),
              3: (1 - 3 * x1 + 1.5 * x1**2 - x1**3 / 6) + (1 - 3 * x2 + 1.5 * x2**2 - x2**3 / 6)}
    return {(p, q): float(np.sum(W * R * (y1**p + y2**p - x1**p - x2**p) * weight[q]))
            for p in (1, 2, 3) for q in (0, 2, 3)}


@pytest.mark.parametrize("alpha", [0.3, 0.8])
def test_second_sonine_of_hard_disks_solves_the_moment_equations_by_quadrature(alpha):
    # Linear in (a2, a3): J_p = J[p, 0] + a2 J[p, 2] + a3 J[p, 3], M2 = 1, M4 = 2(1 + a2),
    # M6 = 6(1 + 3 a2 - a3) (d = 2). HCS: J4 M2 = 2 J2 M4, J6 M2 = 3 J2 M6; white noise: J4 = 4 J2 M2,
    # J6 = 9 J2 M4 (the steady moment equations of tests/sonine_moments.py), products dropped.
    J = _disk_collision_moments(alpha)
    J1, J2, J3 = (np.array([J[p, 0], J[p, 2], J[p, 3]]) for p in (1, 2, 3))
    eqs = {"hcs": (J2 - 4 * J1 - np.array([0, 4 * J1[0], 0]), J3 - 18 * J1 - np.array([0, 54 * J1[0], -18 * J1[0]])),
           "white_noise": (J2 - 4 * J1, J3 - 18 * J1 - np.array([0, 18 * J1[0], 0]))}
    for th, (e4, e6) in eqs.items():
        a2, a3 = np.linalg.solve([e4[1:], e6[1:]], [-e4[0], -e6[0]])
        assert (a2, a3) == pytest.approx(sonine.second_sonine(alpha, th, d=2), abs=1e-12), th
        assert -e4[0] / e4[1] == pytest.approx(sonine.first_sonine_a2(alpha, th, 1, d=2), abs=1e-12), th
