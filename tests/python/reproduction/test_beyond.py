"""Beyond the papers: theory, table builders, verdicts and the report section."""

import math

import numpy as np

from granboltz.reproduction import beyond
from granboltz.report.beyond import compare_beyond_a2, compare_beyond_haff, compare_beyond_tail
from granboltz.report.document import build_document


def test_first_sonine_formulas_at_known_points():
    assert abs(beyond.vne_hcs_a2(0.5) - 4 / 76.25) < 1e-15
    assert abs(beyond.vne_heated_a2(0.5) - 4 / 156.25) < 1e-15
    assert beyond.vne_hcs_a2(1.0) == 0.0 and beyond.vne_heated_a2(1.0) == 0.0


def test_maxwell_references_are_exact_and_flag_the_infinite_eighth_moment():
    a2, kind = beyond.theory_a2("gaussian", 0, 0.5)
    assert abs(a2 - 2 / 7) < 1e-15 and "not valid" not in kind
    assert "not valid" in beyond.theory_a2("gaussian", 0, 0.3)[1]
    a2w, _ = beyond.theory_a2("white_noise", 0, 0.5)
    assert abs(a2w - 2 * 0.25 * 1.5 / (13 - 4.5 + 0.25 - 0.125)) < 1e-15


def test_haff_temperature_maxwell_exact_and_hard_sphere_decay_law():
    T = beyond.haff_temperature([0.0, 10.0], 2.0, 0.5, 1.0, 1 / (4 * math.pi), 0, n=100)
    assert abs(T[0] - 1.98) < 1e-15 and abs(T[1] - 1.98 * math.exp(-0.1875 * 10)) < 1e-12
    Th = beyond.haff_temperature([1e6], 1.0, 0.9, 1.0, 1 / (4 * math.pi), 1)
    assert 0 < Th[0] < 1e-6  # ~ (t0/t)^2


def _a2_row(kind, diff, ci, theory=0.05):
    row = {"thermostat": "white_noise", "kernel": "hard_spheres", "alpha": 0.5, "a2": theory + diff, "ci": ci,
           "theory": theory, "theory_kind": kind, "diff": diff, "z": abs(diff) / (ci / 3.2)}
    agrees = beyond.a2_agrees(row, 0.1, 0.002)
    return {**row, "agrees": agrees, "tol": max(0.1 * abs(theory), 0.002)}


def test_a2_agreement_criteria():
    assert beyond.a2_agrees(_a2_row("van Noije-Ernst", 0.007, 0.002), 0.1, 0.002)  # 0.007 <= 0.005 + 0.002
    assert not beyond.a2_agrees(_a2_row("van Noije-Ernst", 0.008, 0.002), 0.1, 0.002)
    assert beyond.a2_agrees(_a2_row("van Noije-Ernst", 0.0025, 0.001, theory=-0.009), 0.1, 0.002)  # floor
    assert not beyond.a2_agrees(_a2_row("exact", 0.004, 0.003), 0.1, 0.002)  # 4.3 sigma
    assert beyond.a2_agrees(_a2_row("exact; CI not valid", 1.0, 0.001), 0.1, 0.002) is None
    ok, text = beyond.a2_verdict([_a2_row("van Noije-Ernst", 0.008, 0.002)], "white_noise", "hard_spheres")
    assert not ok and text.startswith("differs at α = 0.5")


def test_haff_and_tail_verdicts():
    rows = [{"kernel": "maxwell", "T": 1.0, "z": 1.0}, {"kernel": "maxwell", "T": 1e-3, "z": 3.3}]
    ok, text = beyond.haff_verdict(rows, "maxwell")
    assert not ok and "3.0 decades" in text
    assert beyond.tail_verdict({"r": 8.0, "value": 1.1, "ci": 0.2})[0]
    assert not beyond.tail_verdict({"r": 8.0, "value": 1.5, "ci": 0.2})[0]


def _csv(rows):
    return [{k: ("" if v is None else str(v)) for k, v in r.items()} for r in rows]


def test_report_section_renders_with_its_verdicts():
    haff = _csv([{"kernel": "maxwell", "alpha": 0.9, "n": 10, "N": 2, "t": t, "T": T, "ci": 0.01, "T_theory": T,
                  "ratio": 1.0, "z": 0.5} for t, T in ((0, 1.0), (100, 0.01))])
    a2 = _csv([{**_a2_row("van Noije-Ernst, first Sonine", 0.001, 0.002), "n": 10, "N": 2, "rel_diff": 0.02,
                "published": None, "published_source": ""}])
    tail = _csv([{"alpha": 0.3, "r": 5.0, "b": 1.05, "ci_b": 0.1, "at_bound": 0, "max_ci": 0.2}])
    assert compare_beyond_haff("beyond_haff", haff)[1].startswith("agrees")
    # hard spheres only: a comparison with approximations, whatever the difference
    short = compare_beyond_a2("beyond_a2", a2)[1]
    assert short.kind == "approximation" and "(α 0.5: +0.0510 ± 0.0020 vs +0.0500)" in short
    assert compare_beyond_tail("beyond_hcs_tail_profile", tail)[1].startswith("agrees")
    far = _csv([{"alpha": 0.3, "r": 5.0, "b": 1.6, "ci_b": 0.1, "at_bound": 0, "max_ci": 0.2}])
    short = compare_beyond_tail("beyond_hcs_tail_profile", far)[1]
    assert short.kind == "approximation" and "still above b = 1 where the data end" in short
    items = [{"paper": "Beyond the papers", "item": name, "rule": "beyond_x", "kind": "table", "output": path,
              "what": "w", "runs": [], "benchmarks": ["benchmarks/x.tsv"], "compare": cmp, "published": None, "summary": None, "extra": []}
             for name, path, cmp in (("Haff", "results/tables/beyond_haff.csv", "beyond_haff"),
                                     ("a2", "results/tables/beyond_a2.csv", "beyond_a2"),
                                     ("tail", "results/tables/beyond_hcs_tail_profile.csv", "beyond_tail"))]
    data = {"tables": {items[0]["output"]: haff, items[1]["output"]: a2, items[2]["output"]: tail},
            "published": {}, "summaries": {}, "bench": {}, "runs": {}}
    machine = {k: "x" for k in ("uname", "cpu", "cores", "python", "snakemake", "numpy", "scipy", "h5py", "matplotlib")}
    doc = build_document(items, data, "cfg", machine, "quick")
    assert ("h", 2, "Beyond the papers") in doc
    assert sum(1 for b in doc if b[0] == "h" and b[1] == 3) >= 3


def test_haff_item_verdict_joins_both_kernels_and_fails_with_either():
    good = [{"kernel": "maxwell", "T": 1.0, "z": 1.0}, {"kernel": "maxwell", "T": 1e-3, "z": 2.0},
            {"kernel": "hard_spheres", "T": 1.0, "z": 0.5}, {"kernel": "hard_spheres", "T": 1e-2, "z": 1.5}]
    ok, text, short = beyond.haff_item_verdict(good)
    assert ok and text.startswith("maxwell: agrees within the statistics over 3.0 decades")
    assert "; hard spheres: agrees" in text
    assert short == "agrees within the statistics (maxwell max 2.0σ, 2 times; hard spheres max 1.5σ, 2 times)"
    bad = good[:3] + [{"kernel": "hard_spheres", "T": 1e-2, "z": 3.3}]  # one observation beyond Z
    ok, text, short = beyond.haff_item_verdict(bad)
    assert not ok and "hard spheres: differs" in text and short.startswith("differs (maxwell")
    assert beyond.haff_item_verdict(good[:2])[2] == "agrees within the statistics (maxwell max 2.0σ, 2 times)"


def test_tail_item_verdict_from_the_local_exponents():
    def res(b, ci):
        return {"r": np.array([2.0, 5.0, 8.0]), "b": np.array([2.0, 1.5, b]), "ci_b": np.array([0.01, 0.05, ci]),
                "at_bound": np.array([False, False, False])}
    ok, kind, text, short, far = beyond.tail_item_verdict(res(1.05, 0.1), 0.15)
    assert ok and kind == "agrees" and far == {"r": 8.0, "value": 1.05, "ci": 0.1}
    assert short == "agrees: consistent with b = 1 (b = 1.05 ± 0.10)" and text.startswith("agrees")
    ok, kind, text, short, far = beyond.tail_item_verdict(res(1.4, 0.1), 0.15)  # outside its band: not reached
    assert not ok and kind == "approximation" and text.startswith("still above b = 1")
    assert short.startswith("not yet asymptotic") and short.endswith("(b = 1.40 ± 0.10)")
    ok, kind, text, short, far = beyond.tail_item_verdict(res(1.0, 0.5), 0.001)  # no window narrow enough
    assert (ok, kind, far) == (False, "approximation", None) and text == "no window measures b to ±0.001"
