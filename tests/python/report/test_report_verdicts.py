"""The four outcomes of the report's verdicts: agrees, questioned (a published number far from the
exact result while ours agree with it), approximation (compared with an approximation only) and
differs (ours disagree with an exact result); computed from the numbers of the tables."""

import csv

import pytest

from granboltz.reproduction import beyond
from granboltz.report.convergence import compare_convergence, compare_rw05_table1, compare_rw05_table2
from granboltz.report.numbers import Verdict, combined_kind, exact_verdict, marked, verdict_kind
from granboltz.report.tails import compare_tails, tail_exponent_verdict
from conftest import ROOT


def _csv(path):
    with open(path, newline="", encoding="utf-8") as f:
        return list(csv.DictReader(f))


def test_exact_verdict_outcomes():
    ok = exact_verdict([("n = 64", 1.0), ("n = 256", -2.4)], [("n = 64", 0.5)], 2.0)
    assert ok.kind == "agrees" and ok.startswith("agrees with the exact expectation (max 2.4σ over 2 rows)")
    questioned = exact_verdict([("n = 256", -2.4)], [("n = 256", 3.6)], 4.2)
    assert questioned.kind == "questioned" and "published n = 256 is +3.6σ from it" in questioned
    assert "ours vs published max 4.2σ" in questioned
    bad = exact_verdict([("n = 64", 3.3)], [("n = 64", 9.0)])
    assert bad.kind == "differs" and bad.startswith("differs from the exact expectation: n = 64 +3.3σ")
    assert marked(bad)[0] == "✗" and marked(questioned)[0] == "⚠"


def test_a_verdict_keeps_its_kind_and_refuses_an_unknown_one():
    v = Verdict("approximation", "differs by up to 4 % from first Sonine") + "; more"
    assert verdict_kind(v) == "approximation" and marked(v).startswith("· differs by up to 4 %")
    with pytest.raises(ValueError, match="verdict kind 'none'"):
        Verdict("none", "x")
    assert combined_kind(["approximation", "agrees"]) == "agrees"
    assert combined_kind(["agrees", "questioned", "approximation"]) == "questioned"
    assert combined_kind(["questioned", "differs"]) == "differs"
    assert combined_kind([]) == "approximation"


def _table(name):
    return _csv(ROOT / "tests" / "golden" / "quick_tables" / f"{name}.csv"), _csv(ROOT / "config" / "published" /
                                                                                  f"{name}.csv")


@pytest.mark.parametrize("name, compare", [("grw05_table1", compare_convergence), ("grw05_table2", compare_convergence),
                                           ("rw05_table1", compare_rw05_table1), ("rw05_table2", compare_rw05_table2)])
def test_convergence_tables_are_judged_against_the_exact_expectation(name, compare):
    ours, published = _table(name)
    _, short = compare(name, ours, published)
    assert short.kind in ("agrees", "questioned"), short  # the quick tables agree with the exact errors
    # Ours moved far from the exact expected error in one row: an exact disagreement, whatever the paper says.
    key = "E_max_euler" if name == "rw05_table2" else "E_max"
    moved = [dict(r) for r in ours]
    row = next(r for r in moved if float(r[key]) > float(r[f"{key}_ci"]))
    expected = {"E_max_euler": "E_expected_euler"}.get(key, f"{key}_expected")
    row[key] = str(float(row[expected]) + 5 * float(row[f"{key}_ci"]))
    _, short = compare(name, moved, published)
    assert short.kind == "differs" and short.startswith("differs from the exact"), short


def test_rw05_table1_conf_end_factor_is_questioned():
    ours, published = _table("rw05_table1")
    _, short = compare_rw05_table1("rw05_table1", ours, published)
    assert "published Conf_end is a constant factor" in short and short.kind == "questioned"


def _tail_rows(b_swpm, ci=0.004):
    rows = [{"example": e, "theory_b": str(t), "b": str(b), "b_stderr": "0.005", "fit_window": "[4.25, 4.6]",
             "b_eq38_expected": str(x), "b_swpm": str(s), "b_swpm_ci": str(ci)}
            for e, t, b, x, s in (("7", 1.0, 1.254, 1.270, b_swpm[0]), ("8", 1.5, 1.589, 1.608, b_swpm[1]))]
    pub = {"7": {"published_b": "0.998"}, "8": {"published_b": "1.474"}}
    return rows, pub


def test_tail_exponents_combine_the_window_with_the_weighted_particles():
    rows, pub = _tail_rows((0.999, 1.497))
    v = tail_exponent_verdict(rows, pub)
    assert v.kind == "questioned" and v.startswith("agrees with the exact exponents 1, 1.5")
    assert "as the theory tail with the measured core offset predicts there (1.270, 1.608)" in v
    assert "the published 0.998, 1.474 lie -0.27 (-54 s.e.), -0.13 (-27 s.e.) from that prediction" in v
    far, _ = _tail_rows((0.999, 1.56))
    assert tail_exponent_verdict(far, pub).kind == "differs"  # 0.06 > ci + 0.03 from the exact 1.5
    none = [{k: v for k, v in r.items() if k != "b_swpm"} for r in rows]
    assert tail_exponent_verdict(none, pub).kind == "approximation"
    unresolved = [dict(rows[0], b_swpm="nan"), rows[1]]  # only Ex. 8 resolved: judged on it alone
    v = tail_exponent_verdict(unresolved, pub)
    assert v.kind == "questioned" and "(Ex. 8; the others not resolved to ±0.1)" in v


def test_the_quick_tail_exponent_table_gets_a_computed_verdict():
    ours, published = _table("grw05_tail_exponents")
    _, short = compare_tails("grw05_tail_exponents", ours, published)
    # the quick weighted-particle runs are too small to resolve b: the row says so, and fails nothing
    assert isinstance(short, Verdict) and short.kind == "approximation" and "no weighted-particle b resolved" in short


def _a2(thermostat, kernel, alpha, a2, ci, a3, a3_ci):
    ref, kind = beyond.theory_a2(thermostat, 0 if kernel == "maxwell" else 1, alpha)
    from granboltz.theory.sonine import maxwell_a3, second_sonine

    s2, s3 = second_sonine(alpha, thermostat) if kernel == "hard_spheres" else (None, None)
    return {"thermostat": thermostat, "kernel": kernel, "alpha": alpha, "a2": a2, "ci": ci, "theory": ref,
            "theory_kind": kind, "agrees": 1, "a2_second_sonine": s2, "a3": a3, "a3_ci": a3_ci,
            "a3_second_sonine": s3, "a3_exact": None if s2 is not None else float(maxwell_a3(alpha, thermostat)),
            "a3_valid": 1}


def test_a2_item_is_decided_by_the_exact_maxwell_hierarchy_only():
    from granboltz.theory.sonine import maxwell_a3

    exact3 = float(maxwell_a3(0.8, "white_noise"))
    good = _a2("white_noise", "maxwell", 0.8, beyond.theory_a2("white_noise", 0, 0.8)[0], 0.002, exact3, 0.003)
    hard = _a2("gaussian", "hard_spheres", 0.2, 0.1277, 0.0025, 0.02, 0.004)  # 15 % below first Sonine
    kind, text = beyond.a2_item_verdict([good, hard])
    assert kind == "agrees" and "Maxwell white noise agrees with the exact hierarchy" in text
    assert "first Sonine (van Noije–Ernst) off by up to -0.0222 (α = 0.2)" in text
    kind, _ = beyond.a2_item_verdict([hard])
    assert kind == "approximation"
    off = dict(good, a3=exact3 + 0.006)  # a3 6.4σ from the exact value
    kind, text = beyond.a2_item_verdict([off, hard])
    assert kind == "differs" and "a3 max 6.4σ" in text


def test_a_weighted_particle_tail_fails_only_when_it_resolves_another_exponent():
    from granboltz.analysis.tail_swpm import swpm_kind

    base = {"theory_b": 1.0, "a_theory": 0.73, "a_swpm": 0.74, "a_swpm_ci": 0.01, "depth_swpm": 1e-40,
            "depth_constant": 1e-8, "fit_r_lo": 10.0, "fit_r_hi": 40.0}
    assert swpm_kind({**base, "b_swpm": 0.999, "b_swpm_ci": 0.002}) == "agrees"
    assert swpm_kind({**base, "b_swpm": 1.08, "b_swpm_ci": 0.02}) == "differs"  # 0.08 > 0.02 + 0.03
    assert swpm_kind({**base, "b_swpm": 0.91, "b_swpm_ci": 1.16, "depth_swpm": 3e-9}) == "approximation"
    assert swpm_kind({**base, "b_swpm": float("nan"), "b_swpm_ci": float("nan")}) == "approximation"
