"""The exact moments in the workflow: the GRW05 Ex. 7 moment table against the exact hierarchy, the RW05
moment/Crit comparison, the local-exponent summary and verdicts, and their report sections."""

import csv
import types

import h5py
import numpy as np
import pytest
import yaml

from granboltz.theory import maxwell_hierarchy as mh
from granboltz.analysis.moment_checks import (crit_verdict, hierarchy_physics, moment_rows, moment_verdict,
                                     rw05_moment_rows)
from granboltz.report import item_blocks, render_md, verdict_kind
from granboltz.analysis.tail_local import local_tail_summary, local_verdict, model_local_exponent
from granboltz.analysis.tails import LOCAL_COLUMNS, TAIL_COLUMNS

EX7 = {"alpha": 0.1, "beta": 30.0, "gamma": 16.0, "kernel": {"lambda": 0, "C": 1 / (4 * np.pi)},
       "initial": {"temperature": 1.0}}
RW05 = {"alpha": 0.5, "beta": 1.0, "gamma": 1.0, "kernel": {"lambda": 0, "C": 1 / np.pi}}
LOCAL = {"pool_min_count": 400, "half_width": 4, "step": 2, "far_ci": 0.15, "tail_from": 0.01,
         "paper_window": [4.25, 4.6]}


def _exact_ex7(P=8, t=2.5):
    alpha, beta, nu, T0 = hierarchy_physics({"dsmc": EX7})
    return np.array([mh.evaluate(m, [t])[0] for m in mh.time_dependent_moments(P, alpha, beta, nu, T0)[1:]])


def test_physics_of_the_examples_are_exact_fractions():
    assert hierarchy_physics({"dsmc": EX7}) == (mh.Fraction(1, 10), 30, 16, 1)
    assert hierarchy_physics({"dsmc": {**RW05, "initial": {}}})[2] == 4  # nu = 4 pi C0 gamma
    with pytest.raises(ValueError, match="lambda = 0"):
        hierarchy_physics({"dsmc": {**EX7, "kernel": {"lambda": 1, "C": 0.1}}})


def test_moment_rows_agree_on_the_exact_values_and_name_the_moment_that_differs():
    exact = _exact_ex7()
    rows = moment_rows(exact, 0.01 * exact, *hierarchy_physics({"dsmc": EX7}), 2.5)
    assert [r["p"] for r in rows] == list(range(1, 9))
    assert max(abs(r["sigma"]) for r in rows) < 1e-9
    # t = 2.5 is steady to well under the statistical error (relaxation rate 3.96)
    assert max(abs(r["exact"] / r["exact_steady"] - 1) for r in rows) < 2e-3
    short = moment_verdict(rows)
    assert short.startswith("agrees") and "M_2…M_16" in short and verdict_kind(short) == "agrees"
    shifted = exact.copy()
    shifted[3] *= 1.02  # M_8 two ci away
    short = moment_verdict(moment_rows(shifted, 0.01 * exact, *hierarchy_physics({"dsmc": EX7}), 2.5))
    assert short.startswith("differs: 1 of 8") and "M_8 (+6.4σ)" in short and verdict_kind(short) == "differs"


def _fake_ex7_run(path, P):
    exact = _exact_ex7(P)
    with h5py.File(path, "w") as f:
        f.attrs["config"] = yaml.safe_dump({"model": "dsmc", "dsmc": {**EX7, "particles": 1000, "moments": P}})
        f.attrs["ensembles"] = 4
        f["time"] = np.array([0.0, 2.5])
        for p in range(1, P + 1):
            f[f"moment_{2 * p}/mean"] = np.array([0.0, exact[p - 1] * 1.001])
            f[f"moment_{2 * p}/ci"] = np.array([0.0, exact[p - 1] * 0.01])
    return str(path)


def test_ex7_moment_table_script_writes_p_exact_ours_ci_sigma(run_script, tmp_path):
    out, amp = tmp_path / "m.csv", tmp_path / "a.csv"
    run_script("grw05_ex7_moments.py", input={"runs": [_fake_ex7_run(tmp_path / "r.h5", 10)]},
               output={"csv": str(out), "amplitude": str(amp)}, params={"moments": 8, "pmax": 32})
    rows = list(csv.DictReader(open(out)))
    assert list(rows[0])[:5] == ["p", "exact", "ours", "ci", "sigma"] and len(rows) == 8
    assert all(abs(float(r["sigma"]) - 0.32) < 0.01 for r in rows)  # 0.1 % off, ci 1 % = 3.2 se
    a = list(csv.DictReader(open(amp)))
    assert len(a) == 31 and abs(float(a[-1]["a"]) - 0.7303) < 0.002 and float(a[-1]["a_theory"]) == pytest.approx(
        0.730297, abs=1e-6)
    with pytest.raises(ValueError, match="need M_16"):
        run_script("grw05_ex7_moments.py", input={"runs": [_fake_ex7_run(tmp_path / "s.h5", 4)]},
                   output={"csv": str(out), "amplitude": str(amp)}, params={"moments": 8, "pmax": 32})


def _rw05_run(crit_shift=0.0):
    t = np.linspace(0.0, 8.0, 33)
    alpha, beta, nu, T0 = hierarchy_physics({"dsmc": RW05})
    M = mh.time_dependent_moments(2, alpha, beta, nu, T0)
    M2, M4 = mh.evaluate(M[1], t), mh.evaluate(M[2], t)
    T = M2 / 3
    g = M4 - 15 * T**2 + crit_shift * np.sqrt(120.0) * T**2
    moments = {"pressure_tensor/mean": T[:, None, None] * np.eye(3), "heat_flux/mean": np.zeros((t.size, 3)),
               "fourth_moment/mean": g, "fourth_moment/ci": 0.001 * np.sqrt(120.0) * T**2,
               "moment_4/mean": M4, "moment_4/ci": 0.01 * M4}
    return types.SimpleNamespace(config={"dsmc": RW05}, time=t, n=4096, N=1024, T_centred=T, moments=moments)


def test_rw05_rows_follow_the_exact_curves_and_the_verdict_counts_points_outside():
    rows = rw05_moment_rows(_rw05_run(), [1, 8])
    assert [r["t"] for r in rows] == [1.0, 8.0]
    assert rows[0]["crit_exact"] == pytest.approx(0.08116, abs=1e-5)  # tails.md
    assert rows[1]["crit_exact"] == pytest.approx(0.11887, abs=1e-5)
    assert all(abs(r["crit_sigma"]) < 1e-6 and abs(r["M4_sigma"]) < 1e-9 for r in rows)
    short = crit_verdict(rw05_moment_rows(_rw05_run()))
    assert short.startswith("agrees: exact Crit(t) inside the n = 4096") and verdict_kind(short) == "agrees"
    short = crit_verdict(rw05_moment_rows(_rw05_run(crit_shift=0.002)))  # 2 ci off at t > 0
    assert "33 of 33 point(s) outside" in short and verdict_kind(short) == "differs"


def _shells(density, K=128, R=40.0):
    edges = np.linspace(0.0, R, K + 1)
    r = np.linspace(0.0, R, 40 * K + 1)
    w = 4 * np.pi * r**2 * density(r)
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (w[1:] + w[:-1]) * np.diff(r))])
    frac = np.diff(cum[::40]) / cum[-1]
    counts = np.rint(frac * 1e13)
    return {"edges": edges, "frac": frac, "se": frac / np.sqrt(np.maximum(counts, 1)), "counts": counts}


def test_local_summary_recovers_an_exponential_tail_and_the_verdict_agrees():
    s, curve = local_tail_summary(_shells(lambda r: np.exp(-0.7303 * r)), 15.0, 0.0, 7, LOCAL, [4.0, 4.4])
    assert s["a_fit"] == pytest.approx(0.7303, rel=2e-3) and abs(s["chi_fit"]) < 0.02
    # the offset is that of shell k0 = 1 against r = 0: ln f_1 = c - a <r>_1, <r>_1 = 3h/4
    assert s["offset"] == pytest.approx(-0.7303 * 0.75 * 40 / 128, abs=0.01)
    assert abs(s["b_local_far"] - 1.0) < 0.01 and s["r_far"] > 20
    # no offset: eq. (38) on the window gives b itself (the slope is 1 up to the midpoint shift)
    assert s["b_eq38_expected"] == pytest.approx(1.0, abs=0.01)
    short = local_verdict(s)
    assert short.startswith("agrees: consistent with b = 1") and verdict_kind(short) == "agrees"


def test_local_verdict_differs_for_a_gaussian_tail():
    s, _ = local_tail_summary(_shells(lambda r: np.exp(-r**2 / 30.0)), 5.0, 0.0, 7, LOCAL, [4.0, 4.4])
    assert abs(s["b_local_far"] - 2.0) < 0.02
    short = local_verdict(s)
    assert short.startswith("differs: not consistent with b = 1") and verdict_kind(short) == "differs"


def test_model_local_exponent_tends_to_b_like_chi_over_a_b_r_to_the_b():
    r = np.array([10.0, 1e3, 1e6])
    assert model_local_exponent(0.73, 1.0, 0.0, r) == pytest.approx([1.0] * 3)
    assert model_local_exponent(0.5, 1.5, 0.0, r) == pytest.approx([1.5] * 3)
    assert model_local_exponent(0.73, 1.0, 1.5, 1e6) - 1 == pytest.approx(1.5 / (0.73 * 1e6), rel=1e-4)


def _item(name, compare, output, extra=()):
    return {"paper": "GRW05", "item": name, "rule": "r", "kind": "table", "output": output, "what": "w",
            "runs": [], "benchmarks": [], "compare": compare, "published": None, "summary": None,
            "extra": list(extra)}


def test_report_renders_the_moment_item_and_the_local_exponent_verdicts():
    exact = _exact_ex7()
    rows = moment_rows(exact, 0.01 * exact, *hierarchy_physics({"dsmc": EX7}), 2.5)
    amp = [{"p": p, "ratio": 1.0, "a_chi0": 0.7, "a": 0.73, "chi": 0.4, "a_theory": 0.7303} for p in range(40)]
    data = {"tables": {"m.csv": [{k: str(v) for k, v in r.items()} for r in rows], "a.csv": amp}}
    blocks, short = item_blocks(_item("Ex. 7 moments", "ex7_moments", "m.csv", ["a.csv"]), data)
    text = render_md(blocks)
    assert "### GRW05 Ex. 7 moments" in text and "M_16" in text and "a (χ free)" in text
    assert short.startswith("agrees: M_2…M_16 within")  # p read back from the CSV as text
    s, _ = local_tail_summary(_shells(lambda r: np.exp(-0.7303 * r)), 15.0, 0.0, 7, LOCAL, [4.0, 4.4])
    tail = {c: "1" for c in TAIL_COLUMNS}
    tail.update({"example": "7", "kernel": "maxwell", "b": "1.33", "b_stderr": "0.005", "fit_window": "[4, 4.4]"})
    tail.update({k: str(s[k]) for k in LOCAL_COLUMNS})
    data = {"tables": {"t.csv": [tail]}, "published": {"p.csv": [{"example": "7", "published_b": "0.998"}]}}
    it = _item("Tail exponents", "tails", "t.csv")
    it["published"] = "p.csv"
    blocks, short = item_blocks(it, data)
    text = render_md(blocks)
    assert "Example 7: agrees: consistent with b = 1 where the data reach" in text
    assert "eq. (38) b expected" in text and "the theory tail with the measured core offset predicts" in short
