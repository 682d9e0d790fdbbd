"""Tests of granboltz.theory.tail_theory: the leading-order tail of GRW05 Examples 7-9 and its check by
the growth of the exact lambda = 0 moments (tails.md), and the eq. (38) slope with an offset."""

from fractions import Fraction as F
from math import gamma as Gamma, sqrt

import numpy as np
import pytest

from granboltz.theory import maxwell_hierarchy as mh
from granboltz.theory import tail_theory as tt


def test_examples_7_8_9_leading_order():
    got = {e: tt.example_tail(e) for e in (7, 8, 9)}
    assert [got[e]["b"] for e in (7, 8, 9)] == [1.0, 1.5, 1.25]
    assert [round(got[e]["a"], 3) for e in (7, 8, 9)] == [0.730, 0.487, 0.584]  # tails.md
    assert got[7]["a"] == pytest.approx(sqrt(16 / 30), rel=1e-15)


def test_estimators_are_exact_for_a_pure_gamma_tail():
    a, chi = 0.7, 0.4  # f = r^chi e^{-a r}: M_2p = Gamma(2p+3+chi) / (Gamma(3+chi) a^2p)
    M = [Gamma(2 * p + 3 + chi) / Gamma(3 + chi) / a ** (2 * p) for p in range(12)]
    assert np.allclose(tt.amplitude_from_moments(M, chi), a, rtol=1e-12)
    a_fit, chi_fit = tt.amplitude_and_chi_from_moments(M)
    assert np.allclose(a_fit, a, rtol=1e-9) and np.allclose(chi_fit, chi, atol=1e-8)


@pytest.mark.parametrize("alpha,beta,nu", [(F(1, 10), F(30), F(16)), (F(1, 2), F(1), F(4))])
def test_exact_moments_grow_like_the_leading_order_tail(alpha, beta, nu):
    M = mh.steady_moments(32, alpha, beta, nu)
    a = tt.tail_amplitude(float(nu), float(beta), 0.0)
    a0 = tt.amplitude_from_moments(M)
    a1, chi = tt.amplitude_and_chi_from_moments(M)
    # from p = 10 on the chi = 0 estimate lies below sqrt(nu/beta) and the chi-fitted one above,
    # both converging monotonically; at p = 30 they are within 1 % and 0.5 %
    assert np.all(a0[10:31] < a) and np.all(a1[10:31] > a)
    assert np.all(np.diff(a0[10:31]) > 0) and np.all(np.diff(a1[10:31]) < 0)
    assert abs(a0[30] / a - 1) < 1e-2 and abs(a1[30] / a - 1) < 5e-3
    assert 0 < chi[30] < 1


def test_ex7_chi0_estimates_match_tails_md():
    a0 = tt.amplitude_from_moments(mh.steady_moments(15, F(1, 10), 30, 16))
    assert np.allclose([a0[p] for p in (4, 6, 9, 14)], [0.681, 0.701, 0.713, 0.720], atol=1e-3)


def test_eq38_slope_is_biased_up_by_a_negative_offset():
    a, b = tt.example_tail(7)["a"], 1.0
    unbiased = tt.eq38_slope(a, b, 0.0, radius=40, shells=128)
    assert unbiased == pytest.approx(b, abs=0.01)  # only the shell-midpoint/k0 shift of x remains
    slopes = [tt.eq38_slope(a, b, c, radius=40, shells=128) for c in (0.0, -1.0, -3.0, -5.0)]
    assert np.all(np.diff(slopes) > 0)
    r = 26.0  # mid-window: slope ~ b (1 + |C'| / (a r^b)) to first order
    assert tt.local_eq38_slope(a, b, -0.5, r) == pytest.approx(b * (1 + 0.5 / (a * r)), rel=1e-3)
    c = tt.offset_for_slope(1.254, a, b, radius=40, shells=128)
    assert tt.eq38_slope(a, b, c, radius=40, shells=128) == pytest.approx(1.254, abs=1e-9)
    assert -6 < c < -2


def test_local_slope_is_the_derivative_of_y():
    a, b, c = 0.58, 1.25, -2.0
    r = np.linspace(10, 20, 5)
    h = 1e-6
    y = lambda s: np.log(a * s**b + c)  # noqa: E731
    numeric = (y(r * np.exp(h)) - y(r * np.exp(-h))) / (2 * h)
    assert np.allclose(tt.local_eq38_slope(a, b, c, r), numeric, rtol=1e-7)
