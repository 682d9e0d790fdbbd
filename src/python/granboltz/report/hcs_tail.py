"""The report's comparison of the HCS tail measured with weighted particles (table
beyond_hcs_tail, rule beyond_hcs_tail_swpm): per alpha b against 1 and A against 8 pi gamma C v0/zeta
with the run's own cooling rate, and the depth reached (granboltz.hcs_tail)."""

import math

from ..reproduction.hcs_tail import hcs_tail_row_verdict
from .numbers import Verdict, combined_kind, fl, num, pm

# The targets of config beyond.hcs_tail_swpm (b_tol, A_rel, depth) in both profiles.
B_TOL, A_REL, DEPTH = 0.03, 0.05, 1e-20
B_CI_MAX = 0.1  # a b with a wider interval does not resolve the tail: nothing judged


def row_kind(row, ok, depth=DEPTH):
    """The outcome of one row: agrees where the targets are met; differs where the tail is resolved
    (depth reached, b to ±B_CI_MAX) and b or A miss the exact asymptotics; else approximation (a
    run too small to judge)."""
    if ok:
        return "agrees"
    resolved = (math.isfinite(row["b_swpm"]) and row["b_swpm_ci"] <= B_CI_MAX and row["depth_swpm"] <= depth)
    return "differs" if resolved else "approximation"


def compare_beyond_hcs_tail_swpm(name, ours, published=None, b_tol=B_TOL, A_rel=A_REL, depth=DEPTH, **_):
    """(blocks, short): the table of b, A against A_theory and the depth per alpha; short starts with
    "agrees" when every row meets the targets (|b - 1| <= b_tol, |A/A_theory - 1| <= A_rel, depth <= depth),
    otherwise "differs" and the numbers of the rows that do not."""
    rows = [{k: fl(r[k]) for k in ("alpha", "b_swpm", "b_swpm_ci", "A_swpm", "A_theory", "depth_swpm")} for r in ours]
    if not rows:
        return [("p", "No rows.")], Verdict("approximation", "no rows: nothing measured")
    verdicts = [hcs_tail_row_verdict(r, b_tol, A_rel, depth) for r in rows]
    header = ["α", "b ± CI", "A (fit)", "A = 8πγC v0/ζ", "A/A_theory − 1", "depth f/f(0)", "verdict"]
    body = [[num(r["alpha"]), pm(r["b_swpm"], r["b_swpm_ci"], 3), num(r["A_swpm"], 4), num(r["A_theory"], 4),
             f"{100 * (r['A_swpm'] / r['A_theory'] - 1):+.1f} %", f"{r['depth_swpm']:.1e}",
             "agrees" if ok else "differs"] for r, (ok, _) in zip(rows, verdicts)]
    note = ("Hard spheres under the Gaussian thermostat (the HCS as a steady state), weighted particles (SWPM) with "
            "importance splitting along the thermostat's outward drift. Theory (van Noije & Ernst 1998): f ~ exp(−A c), "
            "c = |v − V|/v0, v0 = √(2T/m), A = 8πγC v0/ζ with ζ = −d ln T/dt measured in the same run (no Sonine "
            "input). A from ln f = c0 + χ ln c − A c (χ free), b from ln f = c0 − a c^b, both over the far tail "
            f"(granboltz.hcs_tail). Targets: |b − 1| ≤ {num(b_tol)}, A within {100 * A_rel:g} %, depth ≤ {depth:.0e}.")
    kinds = [row_kind(r, ok, depth) for r, (ok, _) in zip(rows, verdicts)]
    kind = combined_kind(kinds)
    lead = {"agrees": "agrees with the exact tail", "differs": "differs from the exact tail",
            "approximation": "not resolved at this size"}[kind]
    named = [(k, text) for k, (_, text) in zip(kinds, verdicts) if kind != "differs" or k == "differs"]
    short = lead + " (" + "; ".join(text if k == kind else f"not resolved: {text}" for k, text in named) + ")"
    note += (" Verdict: b = 1 and A = 8πγC v0/ζ are exact for the asymptotic tail; a row that reaches the depth "
             f"with b resolved to ±{B_CI_MAX:g} and misses a target differs from them; a shallower row judges "
             "nothing.")
    return [("table", header, body), ("p", note)], Verdict(kind, short)
