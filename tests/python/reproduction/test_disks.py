"""Hard disks (d = 2) in "Beyond the papers": the references, the energy balance, the rows, their
judgement and verdict (granboltz.reproduction.disks), and the report's comparison."""

import math
import types

import numpy as np
import pytest

from granboltz.reproduction import disks
from granboltz.report.beyond import compare_beyond_disks_a2


def _csv(rows):
    return [{k: ("" if v is None else str(v)) for k, v in r.items()} for r in rows]


def _disk_run(thermostat, alpha, a2, a3, T=1.0, ci=0.002, n=2000, N=40, beta=1.0, C=1 / (2 * math.pi), dim=2):
    obs = lambda mean, c: types.SimpleNamespace(mean=np.float64(mean), ci=np.float64(c))
    dsmc = {"particles": n, "dimension": dim, "alpha": alpha, "beta": beta if thermostat == "white_noise" else 0.0,
            "gamma": 1.0, "kernel": {"lambda": 1, "C": C}, "thermostat": thermostat}
    return types.SimpleNamespace(path=f"{thermostat}-{alpha}.h5", config={"ensembles": N, "dsmc": dsmc},
                                 steady={"a2": obs(a2, ci), "a3": obs(a3, ci), "temperature": obs(T, 0.004)})


def test_disk_steady_temperature_is_the_energy_balance():
    C, alpha, beta = 1 / (2 * math.pi), 0.5, 1.0
    K0 = math.pi**1.5 * C * (1 - alpha**2)
    assert disks.disk_steady_temperature(alpha, beta, 1.0, C) == pytest.approx((2 * beta / K0) ** (2 / 3), rel=1e-14)
    # the Sonine factor of E|u|^3 and the n-particle bias (1 - 1/n)
    T = disks.disk_steady_temperature(alpha, beta, 1.0, C, a2=0.04, a3=-0.01, n=1000)
    assert T == pytest.approx(0.999 * (2 * beta / (K0 * (1 + 0.0075 - 0.01 / 64))) ** (2 / 3), rel=1e-14)
    assert disks.disk_references("white_noise", 0.5) == pytest.approx((0.035635, 0.034524, -0.005496), abs=1e-6)


def test_disk_rows_judge_against_vne_with_the_second_sonine_allowance():
    vne, s2, s3 = disks.disk_references("gaussian", 0.8)  # -0.02194, -0.02551: gap 0.00357
    gap, n = abs(vne - s2), 2000
    tol = 2 * gap + 2 / n * (1 + abs(vne))
    near = vne - 0.002 - tol + 1e-4  # inside ci + tol (ci 0.002)
    rows = disks.disk_a2_rows([_disk_run("gaussian", 0.8, near, s3), _disk_run("gaussian", 0.3, 0.146, -0.07)], 0.01)
    strong, mild = rows  # sorted by alpha
    assert mild["judged"] == 1 and mild["agrees"] == 1 and mild["tol"] == pytest.approx(2 * gap + 2 / n * (1 + abs(near)))
    assert mild["T"] is None and mild["T_agrees"] is None  # the Gaussian thermostat holds T: nothing to compare
    assert strong["judged"] == 0 and strong["agrees"] is None  # the approximations part (gap 0.066)
    assert strong["position"] == pytest.approx((0.146 - 0.113016) / (0.178712 - 0.113016), abs=1e-4)
    assert disks.disk_place(strong) == "between"
    far = disks.disk_a2_rows([_disk_run("gaussian", 0.8, vne - 0.002 - tol - 1e-3, s3)], 0.01)[0]
    assert far["agrees"] == 0 and disks.disk_place(far) == "beyond second Sonine"
    ok, text = disks.disk_a2_verdict(rows, "gaussian")
    assert ok and text.startswith("agrees") and "not judged where the approximations part (α 0.3" in text
    assert not disks.disk_a2_verdict([far], "gaussian")[0]
    assert disks.disk_a2_verdict(rows, "white_noise") == (False, "no runs")
    with pytest.raises(ValueError, match="not a hard-disk run"):
        disks.disk_a2_rows([_disk_run("gaussian", 0.8, vne, s3, dim=3)], 0.01)


def test_disk_white_noise_temperature_against_its_balance():
    alpha, n, beta, C = 0.5, 2000, 1.0, 1 / (2 * math.pi)
    vne, s2, s3 = disks.disk_references("white_noise", alpha)
    T_th = disks.disk_steady_temperature(alpha, beta, 1.0, C, vne, n=n)
    T_tol = T_th * (2 / 3 * (3 / 16 * 2 * abs(vne - s2) + abs(s3) / 64) + 1 / n)
    good = disks.disk_a2_rows([_disk_run("white_noise", alpha, vne, s3, T=T_th + 0.004 + T_tol - 1e-6)], 0.01)[0]
    assert good["T_theory"] == pytest.approx(T_th) and good["T_tol"] == pytest.approx(T_tol) and good["T_agrees"] == 1
    assert good["T_maxwellian"] > good["T_theory"]  # a2 > 0 at alpha 0.5: faster cooling, lower T
    bad = disks.disk_a2_rows([_disk_run("white_noise", alpha, vne, s3, T=T_th + 0.004 + T_tol + 1e-4)], 0.01)[0]
    assert bad["T_agrees"] == 0
    ok, text = disks.disk_a2_verdict([bad], "white_noise")
    assert not ok and "T differs at α = 0.5" in text


def test_disk_report_comparison_recomputes_the_judgement_from_the_table():
    runs = [_disk_run("gaussian", a, disks.disk_references("gaussian", a)[1], -0.01) for a in (0.3, 0.9)]
    alpha, C, n = 0.9, 1 / (2 * math.pi), 2000
    vne, s2, s3 = disks.disk_references("white_noise", alpha)
    runs.append(_disk_run("white_noise", alpha, s2, s3, T=disks.disk_steady_temperature(alpha, 1.0, 1.0, C, vne, n=n)))
    rows = disks.disk_a2_rows(runs, 0.01)
    table = _csv([{**r, "agrees": 0, "judged": 1} for r in rows])  # stale judgements: the comparison recomputes them
    blocks, short = compare_beyond_disks_a2("beyond_disks_a2", table)
    # every d = 2 reference is an approximation: the outcome says so, with the differences
    assert short.kind == "approximation" and "within the allowance where judged" in short
    assert "α = 0.3: position 0.00" in short
    body = blocks[0][2]
    assert [line[9] for line in body] == ["not judged: between, position 0.00", "agrees", "agrees"]
    assert body[2][14] == "agrees" and body[0][14] == "–"


def test_disk_summary_verdict_joins_the_thermostats():
    vne, s2, s3 = disks.disk_references("gaussian", 0.8)
    wv, _, w3 = disks.disk_references("white_noise", 0.8)
    T = disks.disk_steady_temperature(0.8, 1.0, 1.0, 1 / (2 * math.pi), wv, n=2000)
    white = _disk_run("white_noise", 0.8, wv, w3, T=T)
    good = disks.disk_a2_rows([_disk_run("gaussian", 0.8, vne, s3), white], 0.01)
    ok, kind, text, short = disks.disk_summary_verdict(good)
    assert ok and kind == "approximation" and text.startswith("gaussian: agrees")
    assert "; white noise: agrees" in text and short.startswith("compared with approximations: HCS:")
    far = disks.disk_a2_rows([_disk_run("gaussian", 0.8, vne + 0.05, s3), white], 0.01)  # beyond ci + tol
    ok, kind, text, short = disks.disk_summary_verdict(far)
    assert not ok and kind == "approximation" and text.startswith("gaussian: differs at α = 0.8")
    assert "outside the allowance" in short
    assert not disks.disk_summary_verdict(good[:1])[0]  # a thermostat without runs: not shown to agree
