"""granboltz.transport: the exact lambda = 0 rates checked a second way (Monte Carlo of the
collision map itself, and the exact moment hierarchy), the coefficients' elastic limits, and the
hard-sphere first-Sonine values the reference quotes."""

import math

import numpy as np
import pytest

from granboltz.analysis import transport as measured
from granboltz.theory import transport



from granboltz.theory import maxwell_hierarchy
def _collide(v, w, alpha, rng):
    """GRW05 eq. 4 with e uniform on S^{d-1}: the simulator's `geometry: uniform` map."""
    d = v.shape[1]
    e = rng.standard_normal(v.shape)
    e /= np.linalg.norm(e, axis=1)[:, None]
    u = np.linalg.norm(v - w, axis=1)[:, None]
    return 0.5 * (v + w) + (1 - alpha) / 4 * (v - w) + (1 + alpha) / 4 * u * e


def _skewed(n, d, rng):
    """Independent velocities with mean 0, a heat flux along x and a non-Gaussian fourth moment."""
    g = rng.standard_normal((n, d))
    g[:, 0] += 0.4 * (g[:, 0] ** 2 - 1)  # E = 0, E[g^3] != 0
    return g


@pytest.mark.parametrize("d", [2, 3])
@pytest.mark.parametrize("alpha", [0.3, 0.8])
def test_the_heat_flux_rate_is_that_of_the_collision_map(d, alpha):
    # E[v1'_x |v1'|^2] = (1 - nu_Q/nu) <v_x |v|^2> for independent v1, v2 of zero mean: the
    # estimator's own standard error gives the tolerance (family-wise 0.999 over 4 cases).
    rng = np.random.default_rng(17 + d)
    n = 400_000
    v, w = _skewed(n, d, rng), _skewed(n, d, rng)
    vp = _collide(v, w, alpha, rng)
    nu_q = transport.maxwell_rates(alpha, d)["Q"]
    # The mean of (before-after combination) has expectation 0: its own interval decides.
    x = vp[:, 0] * np.sum(vp**2, axis=1) - (1 - nu_q) * v[:, 0] * np.sum(v**2, axis=1)
    assert abs(x.mean()) < 3.5 * x.std() / math.sqrt(n), (x.mean(), x.std() / math.sqrt(n))
    # The test can fail: the d = 3 rate used in d = 2 (or the other way) is far outside.
    other = transport.maxwell_rates(alpha, 5 - d)["Q"]
    y = vp[:, 0] * np.sum(vp**2, axis=1) - (1 - other) * v[:, 0] * np.sum(v**2, axis=1)
    assert abs(y.mean()) > 3.5 * y.std() / math.sqrt(n)


@pytest.mark.parametrize("d", [2, 3])
def test_the_fourth_moment_rates_are_those_of_the_collision_map(d):
    rng = np.random.default_rng(5)
    n, alpha = 400_000, 0.4
    # isotropic, non-Gaussian: a random direction times a speed with a heavy-ish tail
    def draw():
        x = rng.standard_normal((n, d))
        return x / np.linalg.norm(x, axis=1)[:, None] * rng.gamma(3.0, 0.6, n)[:, None]
    v, w = draw(), draw()
    vp = _collide(v, w, alpha, rng)
    c4, c22 = transport.maxwell_fourth_moment_rates(alpha, d)
    s2 = np.sum(v**2, axis=1)
    m2, m4 = 0.6**2 * 3 * 4, 0.6**4 * 3 * 4 * 5 * 6  # <r^2>, <r^4> of Gamma(3, 0.6)
    x = np.sum(vp**2, axis=1) ** 2 - (1 + c4) * s2**2
    assert abs(x.mean() - c22 * m2**2) < 3.5 * x.std() / math.sqrt(n)
    assert abs(m4 - np.mean(s2**2)) < 3.5 * np.std(s2**2) / math.sqrt(n)


def test_d3_rates_agree_with_the_reference_and_the_exact_hierarchy():
    for alpha in (0.2, 0.5, 0.9):
        r = transport.maxwell_rates(alpha)
        assert r["Q"] == pytest.approx((1 + alpha) * (11 - 7 * alpha) / 24, rel=1e-14)
        assert r["Pi"] == pytest.approx((1 + alpha) * (3 - alpha) / 8, rel=1e-14)
        c = [float(x) for x in maxwell_hierarchy.collision_coefficients(2, alpha)]
        c4, c22 = transport.maxwell_fourth_moment_rates(alpha)
        assert (c4, c22) == pytest.approx((c[0] + c[2] - 1, c[1]), rel=1e-13)
        assert transport.maxwell_hcs_a2(alpha) == pytest.approx(float(maxwell_hierarchy.hcs_a2(alpha)), rel=1e-12)


def test_maxwell_coefficients_in_closed_form_and_their_limits():
    for alpha in (0.4, 0.7):
        red = transport.maxwell_reduced(alpha)
        assert red["eta"] == pytest.approx(4 / (1 + alpha) ** 2, rel=1e-13)  # reference: 8p/(nu(1+a)^2)
        assert red["D"] == pytest.approx(2 / (alpha * (1 + alpha)), rel=1e-13)  # 4T/(m nu a(1+a))
        assert red["mu"] > 0
    for d in (2, 3):
        red = transport.maxwell_reduced(1.0, d)
        assert [red[k] for k in ("eta", "kappa", "D")] == pytest.approx([1, 1, 1], rel=1e-12)
        assert red["mu"] == pytest.approx(0, abs=1e-12)
    e = transport.maxwell_coefficients(1.0, nu=2.0, n=1.5, T=0.7, m=1.0)
    assert e["kappa"] / e["eta"] == pytest.approx(15 / 4, rel=1e-13)  # Eucken, Maxwell molecules
    assert math.isnan(transport.maxwell_coefficients(0.2)["kappa"])  # nu_Q = 2 zeta exactly at 1/5
    assert not math.isnan(transport.maxwell_coefficients(0.21)["kappa"])
    assert math.isnan(transport.maxwell_coefficients(0.33, d=2)["mu"])  # d = 2: nu_Q = 2 zeta at 1/3
    assert not math.isnan(transport.maxwell_coefficients(0.34, d=2)["mu"])


def test_hard_sphere_first_sonine_values_of_the_reference():
    # transport.md §3: at alpha = 0.5, kappa* = 1.911 (standard) against 1.630 (modified),
    # eta* = 1.285 against 1.248.
    st = transport.hard_sphere_nu0_coefficients(0.5, "standard")
    mo = transport.hard_sphere_nu0_coefficients(0.5, "modified")
    assert (round(st["kappa"], 3), round(mo["kappa"], 3)) == (1.911, 1.630)
    assert (round(st["eta"], 3), round(mo["eta"], 3)) == (1.285, 1.248)
    for d in (2, 3):
        for version in ("standard", "modified"):
            el = transport.hard_sphere_reduced(1.0, version, d)
            assert all(el[k] == pytest.approx(0 if k == "mu" else 1, abs=1e-12) for k in el)
            assert set(el) == ({"eta", "kappa", "mu", "D"} if d == 3 else {"eta", "D"})
    # With a2 = 0, D/D0 = 4/(1+alpha)^2 in any d; the Sonine a2 moves it by well under 1 %.
    for d in (2, 3):
        assert transport.hard_sphere_reduced(0.8, "standard", d)["D"] == pytest.approx(4 / 1.8**2, rel=0.01)
    with pytest.raises(ValueError, match="version"):
        transport.hard_sphere_reduced(0.5, "third")


@pytest.mark.parametrize("d", [2, 3])
def test_the_exact_hcs_a2_is_the_simulators(d):
    # lambda = 0, geometry uniform, Gaussian thermostat: the steady a2 against maxwell_hcs_a2 of
    # its d, within the run's interval (3.2 sigma over the ensembles' time averages) plus the
    # finite-n bias 2/n (1 + |a2|) (as the C++ SonineExact tests); the other d's value is outside.
    import granboltz

    n = 4000
    dsmc = {"particles": n, "alpha": 0.8, "thermostat": "gaussian",
            "kernel": {"lambda": 0, "C": 0.15915494309189535}, "t_end": 40, "observe_every": 0.5,
            "moments": 2, "steady_from": 15}
    if d == 2:
        dsmc.update(dimension=2, geometry="uniform")
    run = granboltz.simulate({"model": "dsmc", "seed": 3, "ensembles": 60, "dsmc": dsmc}, progress=False)
    a2 = run.steady["a2"]
    exact, other = transport.maxwell_hcs_a2(0.8, d), transport.maxwell_hcs_a2(0.8, 5 - d)
    tolerance = a2.ci + 2 / n * (1 + abs(exact))
    assert abs(a2.mean - exact) < tolerance, (a2.mean, a2.ci, exact)
    assert abs(a2.mean - other) > tolerance, (a2.mean, a2.ci, other)


def test_the_exact_usf_viscosity_tends_to_the_chapman_enskog_eta():
    # Two derivations that share nothing but the collision map: the steady sheared state of the
    # thermostatted second-moment equation (granboltz.shear) at a -> 0, and Chapman-Enskog.
    from granboltz.theory import shear

    C = 0.0795774715459477
    for alpha in (0.5, 0.9):
        a = 1e-4
        eta_usf = -shear.maxwell_gaussian_usf_ratios(alpha, a, 1.0, C)[0, 1] / a
        assert eta_usf == pytest.approx(transport.maxwell_coefficients(alpha, nu=4 * math.pi * C)["eta"], rel=1e-6)


def test_usf_under_the_gaussian_thermostat_extrapolates_to_the_exact_eta():
    # Maxwell molecules, alpha = 0.7: eta(a) = -P_xy/a at a = 0.03, 0.06, 0.09 (in units of the
    # collision rate nu = 1), fitted by eta0 + c a^2 with the runs' own steady intervals. The fit's
    # O(a^4) bias is 0.01 by the exact eta(a), a tenth of the interval. The exact eta (Chapman-
    # Enskog, q = 1) must be inside; p/(nu_Pi - zeta/2), the hard-sphere form, outside.
    import granboltz

    C = 0.0795774715459477
    runs = [granboltz.simulate({"model": "dsmc", "seed": 7, "ensembles": 64,
                                "dsmc": {"particles": 2000, "alpha": 0.7, "thermostat": "gaussian",
                                         "kernel": {"lambda": 0, "C": C}, "shear": {"rate": a}, "t_end": 40,
                                         "observe_every": 0.5, "steady_from": 10}}, progress=False)
            for a in (0.03, 0.06, 0.09)]
    fit = measured.usf_viscosity(runs)
    exact = transport.maxwell_coefficients(0.7)["eta"]
    rates = transport.maxwell_rates(0.7)
    wrong = 1 / (rates["Pi"] - rates["zeta"] / 2)
    assert abs(fit["eta"] - exact) < fit["eta_ci"], fit
    assert abs(fit["eta"] - wrong) > fit["eta_ci"], (fit, wrong)
    with pytest.raises(ValueError, match="no dsmc.shear.rate"):
        measured.usf_viscosity([granboltz.simulate({"model": "dsmc", "seed": 1, "ensembles": 2, "dsmc": {
            "particles": 50, "alpha": 0.7, "thermostat": "gaussian", "kernel": {"lambda": 0, "C": C},
            "t_end": 1, "observe_every": 0.5, "steady_from": 0.5}}, progress=False)])


def test_a_correlation_integral_has_an_interval_that_covers():
    # Ensembles whose rho(t) = e^{-k t} plus noise correlated across lags (an AR(1) in the lag
    # index, as a correlator's neighbouring lags are): the trapezoid integral against its exact
    # value, 2000 synthetic runs of 32 ensembles. The interval (lambda_p = 3.2, 99.86 %) must miss
    # at most 10 times (expected 2.7; Binomial tail < 1e-3); summing per-lag variances as if the
    # lags were independent would be far too narrow and miss often (checked below).
    rng = np.random.default_rng(3)
    # multiple-tau lags: 0..15 steps of 0.05, then j 2^k steps for k = 1..3, j = 8..15
    lags = np.unique(np.concatenate([np.arange(16) * 0.05,
                                     (0.05 * 2.0 ** np.arange(1, 4)[:, None] * np.arange(8, 16)[None, :]).ravel()]))
    k, w, N = 1.3, 0.4, 32
    exact_curve = np.exp(-k * lags)
    c = np.zeros_like(lags)
    h = np.diff(lags)
    c[:-1] += h / 2
    c[1:] += h / 2
    exact = float(c @ (exact_curve * np.exp(-w * lags)))
    misses = naive_misses = 0
    for _ in range(2000):
        noise = np.empty((N, len(lags)))
        noise[:, 0] = rng.standard_normal(N)
        for j in range(1, len(lags)):
            noise[:, j] = 0.9 * noise[:, j - 1] + math.sqrt(1 - 0.81) * rng.standard_normal(N)
        rho = exact_curve + 0.05 * noise
        value, ci = measured.correlation_integral(lags, rho.mean(0), np.cov(rho, rowvar=False), N, weight_rate=w)
        misses += abs(value - exact) > ci
        naive = 3.2 * math.sqrt(np.sum((c * np.exp(-w * lags)) ** 2 * rho.var(0, ddof=1)) / N)
        naive_misses += abs(value - exact) > naive
    assert misses <= 10, misses
    assert naive_misses > 100, naive_misses
    with pytest.raises(ValueError, match="increasing times starting at 0"):
        measured.correlation_integral([0.1, 0.2], [1, 0.5], np.eye(2), 4)
