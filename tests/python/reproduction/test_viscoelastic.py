"""Viscoelastic free cooling (Beyond the papers): the law, the moment equation and its t^(-5/3)
asymptote, the table rows, the late-slope fit, the verdicts, the report table and the script."""

import math
import os
import subprocess
import types

import numpy as np
import pytest
import yaml

from conftest import ROOT
from granboltz.reproduction import beyond
from granboltz.reproduction import viscoelastic as ve
from granboltz.report.beyond import compare_beyond_viscoelastic

BINARY = os.environ.get("GRANBOLTZ_BIN", str(ROOT / "build" / "granboltz"))
C = 1 / (4 * math.pi)


def test_the_law_has_the_constants_of_reference_beyond_section_6():
    assert abs(ve.C1 - 1.1534489) < 1e-7 and abs(ve.C2 - 0.7982666) < 1e-7
    assert abs(ve.X_HOLD - 0.7225) < 1e-4 and ve.restitution(0.0) == 1.0
    eps = ve.restitution([ve.X_HOLD * (1 - 1e-9), ve.X_HOLD, 1.0, 1.445])
    assert np.allclose(eps, 7 / 12, atol=1e-12)  # continuous at the hold, held beyond (the series climbs back)
    x = np.linspace(0, 2, 401)
    assert np.all(np.diff(ve.restitution(x)) <= 0)


def _loss_by_quadrature(T, delta, points=400):
    """The average directly: s = u^2/(4T) ~ Gamma(3) and z = (u.n)^2/u^2 with density 2z (the weight
    |u| g_n^2 of a Maxwellian pair), s = a^10 and z = b^10 so that x = delta (4T)^(1/10) a b is smooth,
    Gauss-Legendre in a in [0, 300^(1/10)] and b in [0, 1]."""
    g, w = np.polynomial.legendre.leggauss(points)
    a_max = 300**0.1
    a, b = np.meshgrid((g + 1) / 2 * a_max, (g + 1) / 2, indexing="ij")
    f = a**20 * np.exp(-(a**10)) / 2 * 10 * a**9 * 2 * b**10 * 10 * b**9
    f *= 1 - ve.restitution(delta * (4 * T) ** 0.1 * a * b) ** 2
    return float(np.einsum("i,j,ij->", w / 2 * a_max, w / 2, f))


@pytest.mark.parametrize("T, delta", [(1.0, 0.05), (1.0, 0.2), (1e-5, 0.2), (1.0, 0.7), (100.0, 0.5)])
def test_loss_fraction_in_closed_form_equals_the_quadrature(T, delta):
    assert abs(ve.loss_fraction(T, delta) - _loss_by_quadrature(T, delta)) < 1e-10


def test_loss_fraction_to_first_and_second_order_in_delta():
    assert abs(ve.A1 - 2 * ve.C1 * 4**0.1 * math.gamma(3.1) / 2 * 2 / 2.1) < 1e-15
    assert abs(ve.A1 - 2.77311) < 1e-5 and abs(ve.B1 - 1.5345) < 1e-4
    for T in (1.0, 1e-4):
        d = 1e-4
        phi = ve.loss_fraction(T, d)
        assert abs(phi / (d * T**0.1) - ve.A1) < 1e-3
        assert abs((phi - ve.A1 * d * T**0.1) / (d * T**0.1) ** 2 + ve.A2) < 1e-3
    assert ve.loss_fraction(1.0, 0.0) == 0.0


def test_tau0_and_the_leading_order_law():
    K0 = 16 / 3 * math.sqrt(math.pi) * C
    assert abs(ve.tau0(0.05, 1.0, 1.0, C) - 1 / (K0 * ve.A1 * 0.05)) < 1e-12
    assert abs(ve.tau0(0.05, 1.0, 1.0, C, n=2000) / ve.tau0(0.05, 1.0, 1.0, C) - 2000 / 1999) < 1e-12
    assert ve.tau0(0.0, 1.0, 1.0, C) == math.inf
    # as delta -> 0 the moment equation is T0 [1 + (3/5) t/tau0]^(-5/3), at equal t/tau0
    d = 1e-5
    t = np.array([1.0, 10.0, 100.0]) * ve.tau0(d, 1.0, 1.0, C)
    ratio = ve.free_cooling_temperature(t, d, 1.0, 1.0, C) / ve.asymptotic_temperature(t, d, 1.0, 1.0, C)
    assert np.all(np.abs(ratio - 1) < 1e-4)
    assert np.all(ve.free_cooling_temperature([0.0, 50.0], 0.0, 0.7, 1.0, C) == 0.7)  # elastic


@pytest.mark.parametrize("delta", [0.05, 0.2])
def test_the_local_slope_tends_to_five_thirds_as_the_first_order_expansion_says(delta):
    t = np.array([3e3, 3e4, 3e5])
    T = ve.free_cooling_temperature(t, delta, 1.0, 1.0, C)
    s = ve.local_slope(t, T, delta, 1.0, C)
    expansion = ve.late_slope_expansion(t, T, delta, ve.tau0(delta, 1.0, 1.0, C))
    assert np.all(np.abs(s - expansion) < 1.5e-3)
    assert np.all(np.abs(s + 5 / 3) < 0.04) and np.all(s < -5 / 3)  # the x^2 term steepens it, slowly
    assert abs(s[-1] + 5 / 3) < abs(s[0] + 5 / 3) or delta < 0.1
    # the finite difference of T agrees with -t zeta(T)
    h = 1e-3
    Tp = ve.free_cooling_temperature(t * (1 + h), delta, 1.0, 1.0, C)
    assert np.all(np.abs(np.log(Tp / T) / math.log1p(h) - s) < 2e-3)


# ----------------------------------------------------------------------------- rows and verdicts
def _run(delta, law=None, N=40, n=2000, t_end=30000.0, dt=15.0, rel_ci=0.0035, a2=-0.01, drift=0.0):
    """A read_run-like object whose T is `law(t)` (default: the moment equation) with a relative CI."""
    t = np.arange(0.0, t_end + dt / 2, dt)
    if law is None:
        law = lambda t: ve.free_cooling_temperature(t, delta, 1 - 1 / n, 1.0, C, n) if delta else np.ones_like(t)
    T = law(t) * (1 + drift * t / t_end)
    obs = lambda mean, ci: types.SimpleNamespace(mean=np.asarray(mean, float), ci=np.asarray(ci, float))
    dsmc = {"particles": n, "gamma": 1.0, "kernel": {"lambda": 1, "C": C}, "initial": {"temperature": 1.0},
            "restitution": {"law": "viscoelastic", "delta": delta}}
    return types.SimpleNamespace(path=f"delta={delta}.h5", config={"ensembles": N, "dsmc": dsmc}, time=t,
                                 temperature=obs(T, rel_ci * T), a2=obs(np.full(t.shape, a2), np.full(t.shape, 0.01)))


def test_rows_carry_log_spaced_times_local_slopes_and_the_late_flag():
    rows = ve.viscoelastic_rows([_run(0.2), _run(0.0, t_end=200.0, dt=10.0)], 40, 3000.0)
    assert [r["delta"] for r in rows][0] == 0.0  # sorted by delta
    elastic, visco = [r for r in rows if r["delta"] == 0], [r for r in rows if r["delta"] == 0.2]
    assert 15 <= len(elastic) <= 20 and all(r["late"] == 0 and r["rel_theory"] == 0 for r in elastic)
    t = [r["t"] for r in visco]
    assert t[0] == 15.0 and t[-1] == 30000.0 and len(t) <= 40 and np.all(np.diff(np.log(t)) > 0.1)
    assert visco[0]["slope"] is None and all(r["slope"] is not None for r in visco[1:])
    assert all(abs(r["slope"] - r["slope_theory"]) < 1e-9 for r in visco[1:])
    assert all(abs(r["rel_theory"]) < 1e-12 for r in visco)
    assert [r["late"] for r in visco] == [int(x >= 3000) for x in t]
    k = 10
    span = math.log(visco[k]["t"] / visco[k - 1]["t"])
    assert abs(visco[k]["slope_ci"] - 2 * 0.0035 / span) < 1e-12  # the two half-widths add
    with pytest.raises(ValueError, match="not a viscoelastic run"):
        ve.run_delta(types.SimpleNamespace(path="x.h5", config={"dsmc": {"alpha": 0.9}}))


def test_late_slope_recovers_a_power_law_and_bounds_its_ci_whatever_the_correlation():
    rows = [{"delta": 0.1, "t": t, "T": 3 * t ** -1.7, "ci": 0.01 * 3 * t ** -1.7, "T_theory": t ** -1.6, "late": 1}
            for t in np.geomspace(100, 1000, 9)]
    fit = ve.late_slope(rows)
    assert abs(fit["value"] + 1.7) < 1e-12 and abs(fit["theory"] + 1.6) < 1e-12 and fit["times"] == 9
    # equal weights: c_i = (x_i - mean x)/sum (x - mean x)^2 and ci = 0.01 sum |c_i|
    x = np.log(np.geomspace(100, 1000, 9))
    assert abs(fit["ci"] - 0.01 * np.sum(np.abs(x - x.mean())) / np.sum((x - x.mean()) ** 2)) < 1e-12
    with pytest.raises(ValueError, match="fewer than 3 late rows"):
        ve.late_slope(rows[:2])


def test_verdict_accepts_the_moment_equation_and_refuses_haff_and_a_drifting_elastic_gas():
    runs = [_run(0.05), _run(0.2), _run(0.0, t_end=200.0, dt=10.0)]
    ok, fits, text = ve.viscoelastic_verdict(ve.viscoelastic_rows(runs, 40, 3000.0))
    assert ok and [f["delta"] for f in fits] == [0.05, 0.2] and all(f["haff_excluded"] for f in fits)
    f = fits[1]
    assert abs(f["value"] - f["theory"]) < 1e-9 and abs(f["approach"] - abs(f["theory"] + 5 / 3)) < 1e-12
    assert abs(f["sonine"] - 5 / 3 * ve.KAPPA * 0.01) < 1e-12  # range of a2 over 0 and -0.01
    assert "Haff's −2 excluded" in text and "δ = 0: T constant" in text
    assert ve.short_verdict(ok, fits).startswith("agrees: T ∝ t^(−5/3)")
    haff = _run(0.2, law=lambda t: (1 + t / 3.0) ** -2.0)
    assert not ve.viscoelastic_verdict(ve.viscoelastic_rows([haff], 40, 3000.0))[0]
    drift = _run(0.0, t_end=200.0, dt=10.0, drift=1e-6)
    ok, text = ve.elastic_verdict(ve.viscoelastic_rows([drift], 40, 3000.0))
    assert not ok and "NOT constant" in text


def test_report_table_recomputes_the_verdict_from_the_csv_cells():
    rows = ve.viscoelastic_rows([_run(0.05), _run(0.0, t_end=200.0, dt=10.0)], 40, 3000.0)
    cells = [{k: "" if v is None else f"{v:.6g}" if isinstance(v, float) else str(v) for k, v in r.items()} for r in rows]
    blocks, short = compare_beyond_viscoelastic("beyond_viscoelastic", cells)
    assert short.startswith("agrees: T ∝ t^(−5/3)") and blocks[0][0] == "table" and len(blocks[0][2]) == 2
    assert blocks[0][2][0][10] == "agrees" and blocks[0][2][0][11] == "excluded"


def test_constant_law_helpers_refuse_a_viscoelastic_run():
    run = _run(0.05)
    with pytest.raises(ValueError, match="viscoelastic runs: granboltz.reproduction.viscoelastic"):
        beyond.run_alpha(run)
    with pytest.raises(ValueError):
        beyond.haff_rows([run])


def test_script_writes_table_figure_and_summary_from_real_runs(run_script, tmp_path):
    if not os.access(BINARY, os.X_OK):
        pytest.fail(f"{BINARY} is missing: build the simulator first (make build)")
    runs = []
    for delta, t_end, every in ((0.2, 3000, 15), (0.0, 50, 5)):
        cfg = {"model": "dsmc", "seed": 7, "ensembles": 4, "dsmc": {
            "particles": 300, "restitution": {"law": "viscoelastic", "delta": delta}, "beta": 0.0, "gamma": 1.0,
            "kernel": {"lambda": 1, "C": C}, "initial": {"temperature": 1.0}, "t_end": t_end,
            "observe_every": every, "thermostat": "none", "majorant": "pairwise"}}
        (tmp_path / f"{delta}.yaml").write_text(yaml.safe_dump(cfg))
        subprocess.run([BINARY, "run", str(tmp_path / f"{delta}.yaml"), "-o", str(tmp_path / f"{delta}.h5"), "-q"],
                       check=True)
        runs.append(str(tmp_path / f"{delta}.h5"))
    out = {k: str(tmp_path / f"v.{k}") for k in ("csv", "png", "pdf")} | {"summary": str(tmp_path / "v.json")}
    log = run_script("beyond_viscoelastic.py", input={"runs": runs}, output=out, params={"rows": 30, "late_from": 300})
    assert "δ = 0: T constant" in log and "δ = 0.2: late slope" in log
    header = open(out["csv"]).readline().strip().split(",")
    assert header[:6] == ["delta", "n", "N", "t", "t_over_tau0", "T"] and header[-1] == "late"
    assert open(out["png"], "rb").read(8) == b"\x89PNG\r\n\x1a\n"
    import json

    summary = json.load(open(out["summary"]))
    assert summary["short"].startswith(("agrees", "differs")) and len(summary["numbers"]["fits"]) == 1
