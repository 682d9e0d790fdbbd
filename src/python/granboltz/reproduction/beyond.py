"""Beyond the papers: free cooling (Haff's law) and the Sonine coefficient a2 of the homogeneous
cooling state (Gaussian thermostat) and the white-noise steady state: the table rows and the
computed verdicts of the report section "Beyond the papers" (viscoelastic free cooling:
granboltz.reproduction.viscoelastic; hard disks: granboltz.reproduction.disks).  The closed forms are
granboltz.theory.hcs (its names are also this module's, for the callers of the old path).

a2 = <c^4>/15 - 1 of the velocities scaled to T = 1, read from a run as the steady average of
`fourth_moment` (M4 - 15 T^2 per sample) over 15 <T>^2.
"""

import math

import numpy as np

from ..analysis.local_exponent import far_estimate
from ..theory.dimension import dsmc_geometry, initial_temperature
from ..theory.sonine import hcs_moment_threshold, maxwell_a3, second_sonine
from ..theory import LAMBDA_P
# the closed forms, also this module's names (the callers of the old module path use them)
from ..theory.hcs import (haff_temperature, theory_a2, vne_hcs_a2, vne_heated_a2)  # noqa: F401


Z = LAMBDA_P  # every confidence half-width of the project (GRW05 §5.1)


# ----------------------------------------------------------------------------- rows
def run_alpha(run):
    """alpha of a run with constant restitution (dsmc.alpha; the stored config has `restitution` in its
    place for another law, e.g. viscoelastic: granboltz.reproduction.viscoelastic); ValueError naming the file otherwise."""
    d = run.config["dsmc"]
    if "alpha" not in d:
        raise ValueError(f"{run.path}: no constant alpha (dsmc.restitution = {d.get('restitution')}); "
                         "viscoelastic runs: granboltz.reproduction.viscoelastic")
    return float(d["alpha"])


def haff_rows(runs):
    """One row per (kernel, observation time) of free-cooling runs (read_run objects): T with its
    half-width, the theory, ratio and sigma-distance z = |T - theory|/(ci/Z)."""
    rows = []
    for run in runs:
        d = run.config["dsmc"]
        n, lam = int(d["particles"]), float(d["kernel"]["lambda"])
        T, ci = run.temperature.mean, run.temperature.ci
        alpha = run_alpha(run)
        th = haff_temperature(run.time, initial_temperature(d), alpha, d["gamma"], d["kernel"]["C"], lam, n,
                              *dsmc_geometry(d))
        for t, x, c, e in zip(run.time, T, ci, th):
            rows.append({"kernel": "maxwell" if lam == 0 else "hard_spheres", "alpha": alpha, "n": n,
                         "N": int(run.config["ensembles"]), "t": float(t), "T": float(x), "ci": float(c),
                         "T_theory": float(e), "ratio": float(x / e), "z": float(abs(x - e) / (c / Z)) if c > 0 else 0.0})
    return rows


def a2_rows(runs, rel_tol, abs_floor, published=()):
    """One row per steady run (read_run objects with steady averages): thermostat, kernel, alpha,
    a2 and its half-width, the reference value and its kind, the difference, sigma-distance,
    relative difference, the tolerance and whether it agrees (a2_agrees); `published` rows
    (alpha, a2, source) of the hard-sphere HCS join by alpha."""
    pub = {round(float(p["alpha"]), 6): p for p in published}
    rows = []
    for run in runs:
        d = run.config["dsmc"]
        lam, th_name = float(d["kernel"]["lambda"]), d.get("thermostat", "white_noise")
        T, fm = run.steady["temperature"], run.steady["fourth_moment"]
        dim, geometry = dsmc_geometry(d)
        a2 = float(fm.mean / (dim * (dim + 2) * T.mean**2))
        ci = float(math.hypot(fm.ci / (dim * (dim + 2) * T.mean**2), 2 * abs(a2) * T.ci / T.mean))
        alpha = run_alpha(run)
        ref, kind = theory_a2(th_name, lam, alpha, dim, geometry)
        p = pub.get(round(alpha, 6)) if (th_name == "gaussian" and lam == 1) else None
        rows.append({"thermostat": th_name, "kernel": "maxwell" if lam == 0 else "hard_spheres",
                     "alpha": alpha, "n": int(d["particles"]), "N": int(run.config["ensembles"]),
                     "a2": a2, "ci": ci, "theory": ref, "theory_kind": kind, "diff": a2 - ref,
                     "z": abs(a2 - ref) / (ci / Z) if ci > 0 else math.inf,
                     "rel_diff": (a2 - ref) / ref if ref else math.nan,
                     "published": float(p["a2"]) if p else None, "published_source": p["source"] if p else ""})
        rows[-1]["tol"] = 0.0 if kind.startswith("exact") else max(rel_tol * abs(ref), abs_floor)
        agrees = a2_agrees(rows[-1], rel_tol, abs_floor)
        rows[-1]["agrees"] = None if agrees is None else int(agrees)
        rows[-1].update(a3_columns(run, th_name, lam, alpha, dim, geometry))
    return sorted(rows, key=lambda r: (r["thermostat"], r["kernel"], r["alpha"]))


def a3_columns(run, thermostat, kernel_lambda, alpha, d=3, geometry=None):
    """The second-Sonine a2 and a3 of hard spheres (beyond.md §1), the simulator's steady a3 with its
    interval (the delta method over the ensembles' time averages, honest for correlated rows), and
    the exact a3 of Maxwell molecules (beyond.md §2; NaN where <c^6> is infinite).  a3_valid: whether
    the a3 interval means anything (the Maxwell HCS needs <c^12> finite, alpha above 0.6647)."""
    a3 = run.steady["a3"]
    hard = kernel_lambda == 1
    s2, s3 = (float(x) for x in second_sonine(alpha, thermostat, d, geometry)) if hard else (None, None)
    exact = None if hard else float(maxwell_a3(alpha, thermostat, d))
    valid = hard or thermostat != "gaussian" or alpha > hcs_moment_threshold(6, d)
    return {"a2_second_sonine": s2, "a3": float(a3.mean), "a3_ci": float(a3.ci), "a3_second_sonine": s3,
            "a3_exact": None if exact is None or math.isnan(exact) else exact, "a3_valid": int(valid)}


def steady_histogram(run, steady_from):
    """Shell data (granboltz.analysis.local_exponent format) of the histogram averaged over the observations
    t_m > steady_from: frac the mean, se = sqrt(sum se_m^2)/M (observations taken as independent)."""
    h = run.histograms["histogram"]
    rows = run.time > steady_from + 1e-12
    se = h["ci"][rows, :-1] / Z
    return {"edges": h["edges"], "frac": h["mean"][rows, :-1].mean(axis=0),
            "se": np.sqrt((se**2).sum(axis=0)) / rows.sum(), "counts": h["counts"][rows, :-1].sum(axis=0),
            "N": int(run.config["ensembles"]), "n": int(run.config["dsmc"]["particles"])}


# ----------------------------------------------------------------------------- verdicts
def haff_verdict(rows, kernel):
    """(ok, text): every observation of `kernel` within the statistics (z <= Z), the decades of T."""
    mine = [r for r in rows if r["kernel"] == kernel]
    worst = max(r["z"] for r in mine)
    decades = math.log10(mine[0]["T"] / mine[-1]["T"])
    ok = worst <= Z
    word = "agrees within the statistics" if ok else "differs"
    return ok, f"{word} over {decades:.1f} decades of T (max {worst:.1f}σ, {len(mine)} times)"


def haff_item_verdict(rows):
    """(ok, text, short) of the Haff item: haff_verdict of each kernel with rows (Maxwell molecules,
    then hard spheres), ok when both agree; short gives each kernel's decades and largest sigma."""
    verdicts = {k: haff_verdict(rows, k) for k in ("maxwell", "hard_spheres") if any(r["kernel"] == k for r in rows)}
    ok = all(v[0] for v in verdicts.values())
    text = "; ".join(f"{k.replace('_', ' ')}: {t}" for k, (_, t) in verdicts.items())
    short = ("agrees within the statistics" if ok else "differs") + " (" + "; ".join(
        f"{k.replace('_', ' ')} {t.split('(')[-1].rstrip(')')}" for k, (_, t) in verdicts.items()) + ")"
    return ok, text, short


def a2_agrees(row, rel_tol, abs_floor):
    """Whether a2 agrees with its reference.  Exact references (Maxwell): within the statistics
    (z <= Z).  First-Sonine references: |a2 - theory| <= ci + tol with tol = rel_tol |theory|, or
    abs_floor where |theory| < abs_floor/rel_tol (near the zero of a2, e.g. alpha = 0.8 for white
    noise, a relative criterion is ill-posed; abs_floor reflects the first Sonine's accuracy).
    None where the reference says the CI is not valid (Maxwell HCS with infinite <c^8>)."""
    if "not valid" in row["theory_kind"]:
        return None  # the variance of the a2 estimator is infinite: no statistical verdict
    if row["theory_kind"].startswith("exact"):
        return row["z"] <= Z
    tol = max(rel_tol * abs(row["theory"]), abs_floor)
    return abs(row["diff"]) <= row["ci"] + tol


def a2_verdict(rows, thermostat, kernel, alphas=None):
    """(ok, text) over the rows (a2_rows, with their `tol` and `agrees`) of one thermostat and
    kernel (those at `alphas` only, if given)."""
    mine = [r for r in rows if r["thermostat"] == thermostat and r["kernel"] == kernel
            and (alphas is None or any(abs(r["alpha"] - a) < 1e-9 for a in alphas))]
    if not mine:
        return False, "no runs"
    skipped = [r for r in mine if r["agrees"] is None]
    mine = [r for r in mine if r["agrees"] is not None]
    if not mine:
        return True, "no statistical verdict (CI not valid at every alpha)"
    bad = [r["alpha"] for r in mine if not r["agrees"]]
    exact = mine[0]["theory_kind"].startswith("exact")
    crit = (f"within the statistics (max {max(r['z'] for r in mine):.1f}σ)" if exact else
            "within the tolerance plus the CI (|Δ| ≤ tol + ci)")
    where = ", ".join(f"{r['alpha']:g}: {r['a2']:+.4f} ± {r['ci']:.4f} vs {r['theory']:+.4f}" for r in mine)
    head = "agrees " if not bad else f"differs at α = {', '.join(f'{a:g}' for a in bad)}; "
    skip = ""
    if skipped:
        listed = ", ".join(f"{r['alpha']:g}" for r in skipped)
        skip = f"; not judged at α = {listed} ({skipped[0]['theory_kind'].split('; ')[-1]})"
    return not bad, f"{head}{crit} (α {where}){skip}"


def a2_item_verdict(rows):
    """(kind, text) of the a2(alpha) item: Maxwell molecules against the exact hierarchy (a2 and a3,
    wherever their intervals are valid: 'agrees' or 'differs'), hard spheres against the first and
    second Sonine approximations, stated as the largest differences (an approximation's accuracy,
    never a failure)."""
    parts, kinds = [], []
    for thermostat, label in (("gaussian", "HCS"), ("white_noise", "white noise")):
        mine = [r for r in rows if r["thermostat"] == thermostat and r["kernel"] == "maxwell"]
        if mine:
            a2s = [r for r in mine if r["agrees"] is not None]
            a3s = [r for r in mine if r.get("a3_exact") is not None and r.get("a3_valid")]
            z2 = [abs(r["a2"] - r["theory"]) / (r["ci"] / Z) for r in a2s if r["ci"] > 0]
            z3 = [abs(r["a3"] - r["a3_exact"]) / (r["a3_ci"] / Z) for r in a3s if r["a3_ci"] > 0]
            bad = max(z2 + z3, default=0.0) > Z
            kinds.append("differs" if bad else "agrees")
            parts.append(f"Maxwell {label} {'differs from' if bad else 'agrees with'} the exact hierarchy "
                         f"(a2 max {max(z2, default=0):.1f}σ at {len(z2)} α, a3 max {max(z3, default=0):.1f}σ at "
                         f"{len(z3)} α)")
        hard = [r for r in rows if r["thermostat"] == thermostat and r["kernel"] == "hard_spheres"]
        if hard:
            first = max(hard, key=lambda r: abs(r["a2"] - r["theory"]))
            second = max(hard, key=lambda r: abs(r["a2"] - r["a2_second_sonine"]))
            kinds.append("approximation")
            parts.append(f"hard spheres {label} against approximations: first Sonine (van Noije–Ernst) off by up to "
                         f"{first['a2'] - first['theory']:+.4f} (α = {first['alpha']:g}), second Sonine by up to "
                         f"{second['a2'] - second['a2_second_sonine']:+.4f} (α = {second['alpha']:g})")
    kind = next((k for k in ("differs", "agrees") if k in kinds), "approximation")
    return kind, {"differs": "differs", "agrees": "agrees", "approximation": "compared"}[kind] + ": " + "; ".join(parts)


def tail_verdict(far, b_expected=1.0):
    """(ok, text) for the outermost well-measured local exponent far = {r, value, ci}: consistent
    with b_expected when |b - b_expected| <= ci; otherwise says how far it is and on which side."""
    ok = abs(far["value"] - b_expected) <= far["ci"]
    text = f"b = {far['value']:.2f} ± {far['ci']:.2f} at |v| = {far['r']:.1f}"
    if ok:
        return True, f"agrees: consistent with b = {b_expected:g}: {text}"
    side = "still above" if far["value"] > b_expected else "below"
    return False, f"{side} b = {b_expected:g} where the data end: {text}"


def tail_item_verdict(res, max_ci, b_expected=1.0):
    """(ok, kind, text, short, far) of the HCS tail item from the local exponents res
    (analysis.local_exponent.local_exponent): tail_verdict of the outermost window that measures b
    to +-max_ci (far, None where none does).  Where b = 1 is not reached the constant weights end
    before the asymptotic tail: an approximation, not a failure."""
    try:
        far = far_estimate(res, max_ci=max_ci)
        ok, text = tail_verdict(far, b_expected)
    except ValueError:
        far, ok, text = None, False, f"no window measures b to ±{max_ci}"
    short = (f"agrees: consistent with b = {b_expected:g}" if ok else
             f"not yet asymptotic where constant weights end (b = {b_expected:g} holds only far out)") + (
        f" (b = {far['value']:.2f} ± {far['ci']:.2f})" if far else "")
    return ok, "agrees" if ok else "approximation", text, short, far
