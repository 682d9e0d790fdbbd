"""granboltz.analysis.finite_size: the fit T(n) = T_inf + c/n recovers a known line, its intervals cover at
their nominal level over synthetic replicas (within binomial limits, fixed seed), and on real
Maxwell-molecule runs it covers the exact T_inf = 8/3 and c = -T_inf of GRW05 Example 3."""

import math
import os
import subprocess

import numpy as np
import pytest
import yaml
from scipy import stats

from granboltz.analysis.finite_size import fit_finite_size
from granboltz.output.run import read_run
from conftest import ROOT

BINARY = os.environ.get("GRANBOLTZ_BIN", str(ROOT / "build" / "granboltz"))
N_SIZES = np.array([16, 32, 64, 128, 256, 512])
SIGMA = 0.02 * np.sqrt(16 / N_SIZES)  # a run's error falls like 1/sqrt(n) at fixed N


def test_an_exact_line_is_recovered_with_zero_chi2():
    fit = fit_finite_size(N_SIZES, 2.5 - 3.0 / N_SIZES, SIGMA)
    assert fit.T_inf == pytest.approx(2.5, abs=1e-12) and fit.c == pytest.approx(-3.0, abs=1e-9)
    assert fit.chi2 == pytest.approx(0.0, abs=1e-18) and fit.dof == 4
    assert fit.cov.shape == (2, 2) and fit.se_T_inf == pytest.approx(math.sqrt(fit.cov[0, 0]))
    assert fit.level == pytest.approx(1 - 2 * stats.norm.sf(3.2))
    lo, hi = fit.T_inf_interval
    assert hi - lo == pytest.approx(2 * 3.2 * fit.se_T_inf)
    assert fit.predict(64) == pytest.approx(2.5 - 3 / 64)
    assert str(fit).startswith("T_inf = 2.500") and "chi2/dof = 0.00" in str(fit)
    with pytest.raises(ValueError):
        fit_finite_size([64, 64], [1.0, 1.0], [0.1, 0.1])


@pytest.mark.parametrize("z", [stats.norm.isf(0.025), 3.2])
def test_the_intervals_cover_at_their_nominal_level(z):
    rng = np.random.default_rng(20240611)
    R, truth = 4000, (2.5, -3.0)
    hits = np.zeros(2, dtype=int)
    chi2 = 0.0
    for _ in range(R):
        T = truth[0] + truth[1] / N_SIZES + rng.normal(0.0, SIGMA)
        fit = fit_finite_size(N_SIZES, T, SIGMA, z=z)
        hits += [fit.T_inf_interval[0] <= truth[0] <= fit.T_inf_interval[1],
                 fit.c_interval[0] <= truth[1] <= fit.c_interval[1]]
        chi2 += fit.chi2
    p = 1 - 2 * stats.norm.sf(z)
    lo, hi = stats.binom.ppf([0.0005, 0.9995], R, p)  # two-sided 99.9 % limits of the count
    assert np.all((lo <= hits) & (hits <= hi)), (hits / R, p, lo / R, hi / R)
    dof = R * (len(N_SIZES) - 2)
    assert stats.chi2.ppf(0.0005, dof) <= chi2 <= stats.chi2.ppf(0.9995, dof)


def _run(tmp_path, n, seed):
    config = {"model": "dsmc", "seed": seed, "ensembles": 40,
              "dsmc": {"particles": int(n), "alpha": 0.5, "beta": 1.0, "gamma": 4.0,
                       "kernel": {"lambda": 0, "C": 1 / (4 * math.pi)}, "t_end": 200.0,
                       "observe_every": 4.0, "steady_from": 8.0}}  # samples 3 relaxation times apart
    cfg, out = tmp_path / f"n{n}.yaml", tmp_path / f"n{n}.h5"
    cfg.write_text(yaml.safe_dump(config))
    subprocess.run([BINARY, "run", str(cfg), "-o", str(out), "-q", "--threads", "1"], check=True)
    return read_run(out)


def test_real_maxwell_runs_cover_the_exact_limit_and_slope(tmp_path):
    if not os.access(BINARY, os.X_OK):
        pytest.fail(f"{BINARY} is missing: build the simulator first (make build)")
    runs = [_run(tmp_path, n, 100 + n) for n in (16, 32, 64, 128, 256)]  # about a second in all
    fit = fit_finite_size(runs)
    exact = 8 / 3  # GRW05 eq. (17): 2 beta / (gamma pi C (1 - alpha^2)); E T_n = (1 - 1/n) T_inf
    assert fit.T_inf_interval[0] <= exact <= fit.T_inf_interval[1], str(fit)
    assert fit.c_interval[0] <= -exact <= fit.c_interval[1], str(fit)
    assert fit.chi2 <= stats.chi2.ppf(0.999, fit.dof)
    by_hand = fit_finite_size([r.config["dsmc"]["particles"] for r in runs], [r.steady["temperature"].mean for r in runs],
                              [r.steady["temperature"].ci / 3.2 for r in runs])
    assert by_hand.T_inf == fit.T_inf and by_hand.se_c == fit.se_c
    with pytest.raises(ValueError, match="differs"):
        (tmp_path / "other").mkdir()
        other = _run(tmp_path / "other", 32, 7)
        other.config["dsmc"]["alpha"] = 0.6
        fit_finite_size(runs + [other])
