"""granboltz.sonine against the numbers of reference/beyond.md (§1 table, §2 values and α_c), the
exact Maxwell hierarchy, quadrature of the Sonine-corrected cooling rate, and GRW05 eq. (17)."""

import math
from fractions import Fraction

import numpy as np
import pytest
from scipy import integrate, special

from granboltz import maxwell_hierarchy as mh
from granboltz import sonine
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
