"""Beyond the papers: the Sonine coefficients a2, a3 of hard disks (d = 2): the table rows, the
judgement and the verdicts of the report item (rule beyond_disks_a2, docs/workflow.md), against
the references of granboltz.theory.disks (its names are also this module's).
"""

from .beyond import run_alpha
# the closed forms, also this module's names (the callers of the old module path use them)
from ..theory.disks import (disk_references, disk_steady_temperature)  # noqa: F401


# Allowances of the hard-disk verdict (as tests/test_dimension.cpp): the error of van Noije-Ernst's
# a2 is taken as GAP_FACTOR times its distance to second Sonine (the next terms no larger than the
# last one), and the O(1/n) bias of the centred moments (docs/output.md: about -2/n, -3/n relative
# for M4, M6) as FINITE_N/n (1 + |a2|).
GAP_FACTOR = 2.0


FINITE_N = 2.0


def disk_a2_rows(runs, max_gap):
    """One row per steady hard-disk run (read_run objects, dsmc.dimension 2, moments >= 3):
    thermostat, alpha, the steady a2, a3 with their half-widths (the simulator's /steady/a2, a3,
    from the ensembles' time averages), the references (van Noije-Ernst a2, second-Sonine a2 and
    a3) and their gap, the allowance tol = GAP_FACTOR gap + FINITE_N/n (1 + |a2|), and under
    white noise T with its balance (disk_steady_temperature with vNE's a2 and the finite-n
    factor; T_maxwellian without the Sonine factor) and allowance T_tol = T_theory (2/3 (3/16
    GAP_FACTOR gap + |a3 second Sonine|/64) + 1/n): 2/3 of the relative error of K.  Judged,
    agrees and position: disk_judge."""
    rows = []
    for run in runs:
        d = run.config["dsmc"]
        if int(d.get("dimension", 3)) != 2 or float(d["kernel"]["lambda"]) != 1:
            raise ValueError(f"{run.path}: not a hard-disk run (dsmc.dimension 2, kernel.lambda 1)")
        geometry = d.get("geometry", "impact")
        th_name, alpha, n = d.get("thermostat", "white_noise"), run_alpha(run), int(d["particles"])
        s = run.steady
        a2 = float(s["a2"].mean)
        vne, s2, s3 = disk_references(th_name, alpha, 2, geometry)
        gap = abs(vne - s2)
        row = {"thermostat": th_name, "alpha": alpha, "n": n, "N": int(run.config["ensembles"]),
               "a2": a2, "a2_ci": float(s["a2"].ci), "a3": float(s["a3"].mean), "a3_ci": float(s["a3"].ci),
               "vne_a2": vne, "sonine2_a2": s2, "sonine2_a3": s3, "gap": gap, "max_gap": float(max_gap),
               "tol": GAP_FACTOR * gap + FINITE_N / n * (1 + abs(a2)), "diff": a2 - vne,
               "T": None, "T_ci": None, "T_theory": None, "T_maxwellian": None, "T_tol": None}
        if th_name == "white_noise":
            beta, gamma, C = float(d["beta"]), float(d["gamma"]), float(d["kernel"]["C"])
            T_th = float(disk_steady_temperature(alpha, beta, gamma, C, vne, n=n, d=2, geometry=geometry))
            row.update(T=float(s["temperature"].mean), T_ci=float(s["temperature"].ci), T_theory=T_th,
                       T_maxwellian=float(disk_steady_temperature(alpha, beta, gamma, C, n=n, d=2, geometry=geometry)),
                       T_tol=T_th * (2 / 3 * (3 / 16 * GAP_FACTOR * gap + abs(s3) / 64) + 1 / n))
        rows.append(disk_judge(row))
    return sorted(rows, key=lambda r: (r["thermostat"], r["alpha"]))


def disk_judge(row):
    """The row with its judgement, from its numbers (so the report recomputes it from the table):
    judged = 1 where gap <= max_gap (the approximations agree well enough for a test), agrees =
    |a2 - vNE| <= a2_ci + tol on judged rows (None elsewhere), position = (a2 - second Sonine) /
    (vNE - second Sonine) (0 at second Sonine, 1 at vNE), T_agrees = |T - T_theory| <= T_ci +
    T_tol (None without T)."""
    judged = row["gap"] <= row["max_gap"]
    has_T = row.get("T") is not None
    return {**row, "judged": int(judged),
            "agrees": int(abs(row["a2"] - row["vne_a2"]) <= row["a2_ci"] + row["tol"]) if judged else None,
            "position": ((row["a2"] - row["sonine2_a2"]) / (row["vne_a2"] - row["sonine2_a2"])
                         if row["gap"] > 0 else None),
            "T_agrees": int(abs(row["T"] - row["T_theory"]) <= row["T_ci"] + row["T_tol"]) if has_T else None}


def disk_place(row):
    """Where a2 falls among the two approximations: 'between', 'beyond second Sonine' (on its
    side, farther from vNE) or 'beyond van Noije-Ernst', each within the row's ci."""
    lo, hi = sorted((row["vne_a2"], row["sonine2_a2"]))
    if lo - row["a2_ci"] <= row["a2"] <= hi + row["a2_ci"]:
        return "between"
    nearer_s2 = abs(row["a2"] - row["sonine2_a2"]) < abs(row["a2"] - row["vne_a2"])
    return "beyond second Sonine" if nearer_s2 else "beyond van Noije-Ernst"


def disk_a2_verdict(rows, thermostat):
    """(ok, text) over the hard-disk rows (disk_a2_rows) of one thermostat: the judged rows agree
    with van Noije-Ernst within ci + tol (and, under white noise, T with its balance); the rows
    where the approximations part (gap > max_gap) are not judged: the text says where a2 falls
    among them."""
    mine = [r for r in rows if r["thermostat"] == thermostat]
    if not mine:
        return False, "no runs"
    judged = [r for r in mine if r["judged"]]
    bad = [r["alpha"] for r in judged if not r["agrees"]]
    bad_T = [r["alpha"] for r in mine if r["T_agrees"] is not None and not r["T_agrees"]]
    parts = []
    if judged:
        where = ", ".join(f"{r['alpha']:g}: {r['a2']:+.4f} ± {r['a2_ci']:.4f} vs {r['vne_a2']:+.4f} "
                          f"(second Sonine {r['sonine2_a2']:+.4f})" for r in judged)
        head = "agrees" if not bad else f"differs at α = {', '.join(f'{a:g}' for a in bad)}"
        parts.append(f"{head}: |a2 − vNE| ≤ ci + {GAP_FACTOR:g}|vNE − 2nd Sonine| + {FINITE_N:g}/n(1 + |a2|) "
                     f"(α {where})")
    parted = [r for r in mine if not r["judged"]]
    if parted:
        where = ", ".join(f"{r['alpha']:g}: {r['a2']:+.4f} ± {r['a2_ci']:.4f}, {disk_place(r)} (second Sonine "
                          f"{r['sonine2_a2']:+.4f}, vNE {r['vne_a2']:+.4f}; position {r['position']:.2f})"
                          for r in parted)
        parts.append(f"not judged where the approximations part (α {where})")
    with_T = [r for r in mine if r["T_agrees"] is not None]
    if with_T:
        head = "T agrees" if not bad_T else f"T differs at α = {', '.join(f'{a:g}' for a in bad_T)}"
        parts.append(f"{head} with the balance (max |T/theory − 1| "
                     f"{max(abs(r['T'] / r['T_theory'] - 1) for r in with_T):.2%})")
    return not bad and not bad_T, "; ".join(parts)


def disk_item_verdict(rows):
    """(kind, text) of the hard-disk item: every reference in d = 2 is an approximation (van
    Noije-Ernst's first Sonine, the second Sonine, the energy balance with vNE's a2), so the outcome
    is 'approximation' and the text gives the largest measured differences and whether they lie
    within the allowance of disk_judge."""
    parts = []
    for thermostat, label in (("gaussian", "HCS"), ("white_noise", "white noise")):
        mine = [r for r in rows if r["thermostat"] == thermostat]
        if not mine:
            continue
        ok, _ = disk_a2_verdict(rows, thermostat)
        first = max(mine, key=lambda r: abs(r["a2"] - r["vne_a2"]))
        second = max(mine, key=lambda r: abs(r["a2"] - r["sonine2_a2"]))
        text = (f"{label}: a2 − vNE up to {first['a2'] - first['vne_a2']:+.4f} (α = {first['alpha']:g}), a2 − second "
                f"Sonine up to {second['a2'] - second['sonine2_a2']:+.4f} (α = {second['alpha']:g}); "
                f"{'within' if ok else 'outside'} the allowance where judged")
        with_T = [r for r in mine if r["T"] is not None]
        if with_T:
            text += f", T within {max(abs(r['T'] / r['T_theory'] - 1) for r in with_T):.2%} of the balance"
        parted = [r for r in mine if not r["judged"]]
        if parted:
            text += "; where the approximations part, " + ", ".join(
                f"α = {r['alpha']:g}: position {r['position']:.2f}" for r in parted) + " (0: second Sonine, 1: vNE)"
        parts.append(text)
    return "approximation", "compared with approximations: " + "; ".join(parts)


def disk_summary_verdict(rows):
    """(ok, kind, text, short) of the hard-disk item: the text joins disk_a2_verdict of each
    thermostat (ok when both hold), the kind and short are disk_item_verdict's."""
    verdicts = {t: disk_a2_verdict(rows, t) for t in ("gaussian", "white_noise")}
    ok = all(v[0] for v in verdicts.values())
    text = "; ".join(f"{t.replace('_', ' ')}: {v}" for t, (_, v) in verdicts.items())
    kind, short = disk_item_verdict(rows)
    return ok, kind, text, short
