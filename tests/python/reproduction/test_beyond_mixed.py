"""The mixture and rough-sphere items of "Beyond the papers": rows, intervals and verdicts
(granboltz.reproduction.mixtures.mixture_rows, granboltz.reproduction.rough.rough_rows), the report's comparisons, and the
two workflow scripts on synthetic runs."""

import math
import types

import numpy as np
import pytest

from granboltz.reproduction import mixtures, rough
from granboltz.report.beyond import compare_beyond_mixture, compare_beyond_rough
from granboltz.report.numbers import verdict_kind


def _obs(mean, sigma, z=3.2):
    return types.SimpleNamespace(mean=np.float64(mean), sigma=np.float64(sigma), ci=np.float64(z * sigma))


def _mixture_run(mass_ratio, alpha, T1, T2, s1=0.002, s2=0.002, s_mix=None, x1=0.5, n=1000, N=10, s_ratio=None):
    """A stand-in for read_run of a Gaussian-thermostat binary mixture (T = x1 T1 + x2 T2), with the
    simulator's stored T1/T2 (sigma s_ratio; default the delta method at correlation -1)."""
    x2 = 1 - x1
    s_mix = abs(x1 * s1 - x2 * s2) if s_mix is None else s_mix  # the thermostat holds T: correlation -1
    s_ratio = T1 / T2 * (s1 / T1 + s2 / T2) if s_ratio is None else s_ratio
    species = {"heavy": types.SimpleNamespace(mass=float(mass_ratio), diameter=1.0, fraction=x1,
                                              steady={"temperature": _obs(T1, s1)}),
               "light": types.SimpleNamespace(mass=1.0, diameter=1.0, fraction=x2,
                                              steady={"temperature": _obs(T2, s2)})}
    dsmc = {"particles": n, "alpha": alpha, "thermostat": "gaussian",
            "species": [{"name": "heavy", "fraction": x1}, {"name": "light", "fraction": x2}]}
    return types.SimpleNamespace(path=f"m{mass_ratio}-{alpha}.h5", config={"ensembles": N, "dsmc": dsmc},
                                 species=species, steady={"temperature": _obs(x1 * T1 + x2 * T2, s_mix),
                                                          "temperature_ratio/heavy_over_light": _obs(T1 / T2, s_ratio)})


def test_the_correlation_from_the_mixture_temperature():
    # T = x1 T1 + x2 T2 held exactly: x1 s1 = x2 s2 and Var T = 0 give correlation -1
    assert mixtures.mixture_correlation(0.01, 0.01, 0.0, 0.5, 0.5) == pytest.approx(-1.0)
    # independent estimates: Var T = x1^2 s1^2 + x2^2 s2^2
    assert mixtures.mixture_correlation(0.01, 0.02, math.hypot(0.005, 0.01), 0.5, 0.5) == pytest.approx(0.0, abs=1e-12)
    assert mixtures.mixture_correlation(0.01, 0.01, 1.0, 0.5, 0.5) == 1.0  # clipped
    assert mixtures.mixture_correlation(0.0, 0.01, 0.0, 0.5, 0.5) == 0.0


def test_mixture_rows_and_verdict():
    gd = mixtures.temperature_ratio("gaussian", 4, 0.8)  # 1.3412
    T2 = 2 / (1 + gd * 1.02)  # ours 2 % above GD, x1 T1 + x2 T2 = 1
    gd2 = mixtures.temperature_ratio("gaussian", 2, 0.9)
    rows = mixtures.mixture_rows([_mixture_run(4, 0.8, gd * 1.02 * T2, T2), _mixture_run(2, 0.9, gd2, 1.0)])
    assert [(r["mass_ratio"], r["alpha"]) for r in rows] == [(2.0, 0.9), (4.0, 0.8)]
    row = rows[1]
    assert row["t1_t2"] == pytest.approx(gd * 1.02) and row["difference"] == pytest.approx(0.02)
    assert row["t1_t2_garzo_dufty"] == pytest.approx(1.3412, abs=5e-5) and row["correlation"] == pytest.approx(-1.0)
    s = row["t1_t2"] * (0.002 / row["T1"] + 0.002 / row["T2"])  # the stored interval, as it is
    assert row["t1_t2_ci"] == pytest.approx(3.2 * s)
    assert mixtures.mixture_rows([_mixture_run(2, 0.9, 1.0, 1.0, s_ratio=0.0125)])[0]["t1_t2_ci"] == pytest.approx(0.04)
    ours, short = mixtures.mixture_verdict(rows)
    assert short.startswith("compared with an approximation (Maxwellian") and "+2.0%" in short
    assert verdict_kind(short) == "approximation"  # a comparison with an approximation is never a failure
    assert "m1/m2 = 4: α 0.8" in ours and "+2.00%" in ours
    with pytest.raises(ValueError, match="binary mixture"):
        bad = _mixture_run(2, 0.9, 1.0, 1.0)
        bad.species.pop("light")
        mixtures.mixture_rows([bad])
    old = _mixture_run(2, 0.9, 1.0, 1.0)
    del old.steady["temperature_ratio/heavy_over_light"]
    with pytest.raises(ValueError, match="no /steady/temperature_ratio/heavy_over_light"):
        mixtures.mixture_rows([old])


def _rough_run(thermostat, alpha, beta, T_tr, T_rot, s=0.001, kappa=0.4, n=1000, N=10, s_theta=None, d=3, lam=1):
    """A stand-in for read_run of rough particles with the simulator's stored theta (sigma s_theta;
    default the delta method at correlation -1, the Gaussian thermostat's)."""
    dsmc = {"particles": n, "alpha": alpha, "thermostat": thermostat, "roughness": {"beta": beta, "inertia": kappa},
            "kernel": {"lambda": lam}, "dimension": d}
    s_theta = T_rot / T_tr * (s / T_rot + s / T_tr) if s_theta is None else s_theta
    return types.SimpleNamespace(path=f"{thermostat}-{alpha}-{beta}.h5", config={"ensembles": N, "dsmc": dsmc},
                                 steady={"temperature": _obs(T_tr, s), "temperature_rotational": _obs(T_rot, s),
                                         "theta": _obs(T_rot / T_tr, s_theta)})


def test_rough_rows_and_verdict():
    th = rough.hcs_theta(0.9, 0.5)  # 0.8671
    T_tr = 2 / (1 + 0.955 * th)  # 4.5 % below, T_tr + T_rot = 2
    rows = rough.rough_rows([_rough_run("gaussian", 0.9, 0.5, T_tr, 2 - T_tr),
                             _rough_run("white_noise", 0.9, 0.5, 3.0, 3.0 * rough.white_noise_theta(0.5) * 1.005)])
    hcs, wn = rows
    assert hcs["theta"] == pytest.approx(0.955 * th) and hcs["difference"] == pytest.approx(-0.045)
    assert hcs["theta_maxwellian"] == pytest.approx(0.8671, abs=5e-5)
    assert hcs["theta_ci"] == pytest.approx(3.2 * hcs["theta"] * (0.001 / hcs["T_rot"] + 0.001 / hcs["T_tr"]))
    assert wn["difference"] == pytest.approx(0.005) and wn["theta_maxwellian"] == pytest.approx(0.4615, abs=5e-5)
    ours, short = rough.rough_verdict(rows)
    assert short == "compared with an approximation (Maxwellian), differs by HCS -4.5%, white noise +0.5%"
    assert verdict_kind(short) == "approximation" and "1 of 1 outside" in ours
    with pytest.raises(ValueError, match="not a rough-sphere run"):
        bad = _rough_run("gaussian", 0.9, 0.5, 1, 1)
        del bad.config["dsmc"]["roughness"]
        rough.rough_rows([bad])
    # the stored interval as it is (white noise: narrower than the -1 correlation's), the run's d
    wn = rough.rough_rows([_rough_run("white_noise", 0.9, 0.5, 3.0, 1.4, s_theta=1e-4)])[0]
    assert wn["theta_ci"] == pytest.approx(3.2e-4)
    disk = rough.rough_rows([_rough_run("gaussian", 0.9, 0.5, 1.0, 0.8, kappa=0.5, d=2)])[0]
    assert disk["theta_maxwellian"] == pytest.approx(rough.hcs_theta(0.9, 0.5, 0.5, d=2)) and disk["d"] == 2
    assert "HCS (disks)" in rough.rough_verdict([disk])[1]
    old = _rough_run("gaussian", 0.9, 0.5, 1, 1)
    del old.steady["theta"]
    with pytest.raises(ValueError, match="no /steady/theta"):
        rough.rough_rows([old])
    with pytest.raises(ValueError, match="kernel.lambda 1"):
        rough.rough_rows([_rough_run("gaussian", 0.9, 0.5, 1, 1, lam=0)])


def _csv(rows):
    return [{k: ("" if v is None else str(v)) for k, v in r.items()} for r in rows]


def test_report_comparisons_from_the_tables():
    gd = mixtures.temperature_ratio("gaussian", 2, 0.7)
    rows = mixtures.mixture_rows([_mixture_run(2, 0.7, gd, 1.0)])
    blocks, short = compare_beyond_mixture("beyond_mixture", _csv(rows))
    assert blocks[0][0] == "table" and blocks[0][2][0][6] == "+0.00%" and short.startswith("compared")
    rows = rough.rough_rows([_rough_run("gaussian", 0.7, 0.0, 1.0, rough.hcs_theta(0.7, 0.0))])
    blocks, short = compare_beyond_rough("beyond_rough", _csv(rows))
    assert blocks[0][2][0][7] == "1.2192" and "HCS +0.0%" in short
