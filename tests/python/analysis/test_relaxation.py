"""Transport coefficients from relaxation (granboltz.relaxation) against the exact Maxwell-molecule
values (lambda = 0, geometry uniform, Gaussian thermostat): a prepared shear stress decays at
nu_Pi - zeta and gives eta, a prepared heat flux decays at nu_Q - 3 zeta/2 and gives kappa.
Replicas of the run test both the exactness (their mean rate against the exact one within the
Student-t interval of their spread) and the single run's interval (it must cover in at least
as many replicas as its level promises; being a bound, it may cover more)."""

import math

import numpy as np
import pytest
from scipy import stats

import granboltz
from granboltz.analysis import relaxation
from granboltz.theory import transport
from granboltz.theory import LAMBDA_P

C = 1 / (4 * math.pi)  # nu = 1


def _run(initial, alpha, seed, n=2000, ensembles=40, t_end=4):
    return granboltz.simulate({"model": "dsmc", "seed": seed, "ensembles": ensembles, "dsmc": {
        "particles": n, "alpha": alpha, "beta": 0, "gamma": 1, "kernel": {"lambda": 0, "C": C},
        "thermostat": "gaussian", "t_end": t_end, "observe_every": 0.25, "initial": initial}},
        progress=False)


def _replicas(initial, alpha, measure, R=30):
    return [measure(_run(initial, alpha, seed=100 + k)) for k in range(R)]


def _check(results, key, exact):
    values = np.array([r[key] for r in results])
    cis = np.array([r[f"{key}_ci"] for r in results])
    R = len(values)
    # Exactness: the replicas' mean against the exact value, Student-t at lambda_p's level.
    level = 2 * stats.norm.cdf(LAMBDA_P) - 1
    half = stats.t.ppf(0.5 + level / 2, R - 1) * values.std(ddof=1) / math.sqrt(R)
    assert abs(values.mean() - exact) <= half, (key, values.mean(), half, exact)
    # Coverage: each run's interval holds the exact value (a bound: at least the level).
    misses = int(np.sum(np.abs(values - exact) > cis))
    assert misses <= stats.binom.ppf(0.999, R, 1 - level), (key, misses)
    # The spread over the mean sigma the intervals claim: about 0.5 measured (a bound is wider
    # than the spread by the rows' correlation it cannot see); above 1.33 it would be too narrow.
    return values.std(ddof=1) / (cis.mean() / LAMBDA_P)


def test_a_prepared_shear_stress_gives_the_exact_viscosity():
    alpha = 0.5
    rates = transport.maxwell_rates(alpha)
    results = _replicas({"temperature": [[1, 0.4, 0], [0.4, 1, 0], [0, 0, 1]]}, alpha,
                        lambda r: relaxation.viscosity_from_relaxation(r, window=(0, 3)))
    _check(results, "rate", rates["Pi"] - rates["zeta"])
    assert _check(results, "eta", transport.maxwell_coefficients(alpha)["eta"]) <= 1.33


def test_a_prepared_heat_flux_gives_the_exact_conductivity():
    alpha = 0.8
    rates = transport.maxwell_rates(alpha)
    a2 = transport.maxwell_hcs_a2(alpha)
    results = _replicas({"heat_flux": [0.19, 0, 0]}, alpha,
                        lambda r: relaxation.conductivity_from_relaxation(r, a2, rates["zeta"],
                                                                          window=(0, 3)))
    _check(results, "rate", rates["Q"] - 1.5 * rates["zeta"])
    assert _check(results, "kappa", transport.maxwell_coefficients(alpha)["kappa"]) <= 1.33


def test_decay_rate_of_an_exact_exponential_and_its_refusals():
    t = np.linspace(0, 2, 9)
    fit = relaxation.decay_rate(t, -3 * np.exp(-0.7 * t), np.zeros_like(t))
    assert fit["rate"] == pytest.approx(0.7) and fit["amplitude"] == pytest.approx(-3)
    assert fit["rate_ci"] == 0
    with pytest.raises(ValueError, match="changes sign"):
        relaxation.decay_rate(t, np.cos(3 * t), np.full_like(t, 0.01))
    with pytest.raises(ValueError, match="1 rows in the window"):
        relaxation.decay_rate(t, np.exp(-t), np.full_like(t, 0.01), window=(0.1, 0.3))
    run = _run({"temperature": 1}, 0.5, seed=1, ensembles=2, n=200, t_end=1)
    run.config["dsmc"]["thermostat"] = "none"
    with pytest.raises(ValueError, match="Gaussian thermostat"):
        relaxation.viscosity_from_relaxation(run)
