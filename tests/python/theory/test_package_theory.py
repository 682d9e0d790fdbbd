"""granboltz.theory against known values: GRW05 eqs. (16)-(17), the Euler and Strang step maps
of RW05, the estimator's bias, and the TV06 formulas of §3.1."""

import math

import numpy as np
import pytest
from scipy import integrate, stats

from granboltz.theory import (analytic_temperature, exact_temperature_ratio, gaussian_fluxes, gaussian_pdf,
                              gaussian_temperature_ratio, powerlaw_pdf, scheme_steady_temperature, scheme_temperature,
                              t_coverage, uncentred_expectation)

RW05 = dict(alpha=0.5, beta=1.0, gamma=1.0, C0=1 / math.pi)  # k = 3/4, T_inf = 8/3 (RW05 eq. 25)


def test_heated_maxwell_temperature_grw05_eq16():
    t = np.array([0.0, 1.0, 4.0, 200.0])
    T = analytic_temperature(t, 1.0, **RW05)
    np.testing.assert_allclose(T, np.exp(-0.75 * t) + 8 / 3 * (1 - np.exp(-0.75 * t)), rtol=1e-14)
    assert T[-1] == pytest.approx(8 / 3, rel=1e-14)
    # elastic: no cooling, the kicks heat linearly
    np.testing.assert_allclose(analytic_temperature(t, 2.0, 1.0, 0.5, 1.0, 1 / math.pi), 2.0 + t, rtol=1e-15)


def test_scheme_step_maps_and_their_fixed_points():
    dt, k = 0.5, 0.75
    T, Ts = [1.0], [1.0]
    for _ in range(8):  # Euler: collisions for dt, then kicks; Strang: half, kicks, half
        T.append(math.exp(-k * dt) * T[-1] + 2 * dt)
        Ts.append(math.exp(-k * dt / 2) * (math.exp(-k * dt / 2) * Ts[-1] + 2 * dt))
    t = np.arange(9) * dt
    np.testing.assert_allclose(scheme_temperature("euler", t, dt, 1.0, **RW05), T, rtol=1e-13)
    np.testing.assert_allclose(scheme_temperature("strang", t, dt, 1.0, **RW05), Ts, rtol=1e-13)
    assert scheme_steady_temperature("nosplit", None, **RW05) == pytest.approx(8 / 3, rel=1e-15)
    assert scheme_steady_temperature("euler", dt, **RW05) == pytest.approx(2 * dt / (1 - math.exp(-k * dt)))
    # Euler is first order in dt, Strang second order (RW05 Table 2)
    err = {s: [abs(scheme_steady_temperature(s, h, **RW05) - 8 / 3) for h in (0.1, 0.05)] for s in ("euler", "strang")}
    assert err["euler"][0] / err["euler"][1] == pytest.approx(2, rel=0.05)
    assert err["strang"][0] / err["strang"][1] == pytest.approx(4, rel=0.05)
    with pytest.raises(ValueError, match="multiples of dt"):
        scheme_temperature("euler", [0.3], dt, 1.0, **RW05)


def test_uncentred_estimator_bias():
    # E |v|^2/3 = (1 - 1/n) T + (T0 + 2 beta t)/n; at n = 1 only the bulk velocity's walk is left
    assert uncentred_expectation(2.0, 3.0, 1.0, 1.0, 1) == pytest.approx(7.0)
    assert uncentred_expectation(2.0, 3.0, 1.0, 1.0, 100) == pytest.approx(2.0 * 0.99 + 0.07)


def test_tv06_baths_and_rates():
    a = 0.5
    for pdf, T_B in ((gaussian_pdf, 1 / (2 * a)), (powerlaw_pdf, 1 / a)):
        assert integrate.quad(lambda v: pdf(v, a), -np.inf, np.inf)[0] == pytest.approx(1, abs=1e-10)
        assert integrate.quad(lambda v: v**2 * pdf(v, a), -np.inf, np.inf)[0] == pytest.approx(T_B, rel=1e-8)
    plus, minus, total = gaussian_fluxes(0.0, a)
    assert plus == minus == pytest.approx(0.5 / math.sqrt(math.pi * a), rel=1e-15)
    for v1 in (0.3, 2.0, -1.5):  # eqs. (15)-(16): phi_+ - phi_- = rho v1
        plus, minus, total = gaussian_fluxes(v1, a, rho=2.0)
        assert plus - minus == pytest.approx(2.0 * v1, rel=1e-12) and total == pytest.approx(plus + minus)


def test_tv06_temperature_ratios():
    assert gaussian_temperature_ratio(0.5, 1.0) == pytest.approx(0.6)  # (1 + a)/(2 + (1 - a)/M), eq. (18)
    assert gaussian_temperature_ratio(1.0, 0.3) == pytest.approx(1.0)
    assert exact_temperature_ratio("gaussian", 0.0, 1.0) == pytest.approx(1 / 3)
    assert exact_temperature_ratio("powerlaw", 0.3, 0.3) == pytest.approx(0.3)  # M = alpha, any bath
    assert exact_temperature_ratio("powerlaw", 0.3, 1.0) is None


def test_coverage_of_the_simulators_interval():
    assert t_coverage(10) == pytest.approx(0.986, abs=5e-4)
    assert t_coverage(10**7) == pytest.approx(1 - 2 * stats.norm.sf(3.2), abs=1e-6)
    assert math.isnan(t_coverage(1))
