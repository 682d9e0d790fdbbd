"""Free cooling of viscoelastic hard spheres (Beyond the papers): the table rows, the late-slope fit
and the verdicts of the report item, against the moment equation of granboltz.theory.viscoelastic
(its names are also this module's).
"""

import math

import numpy as np

from .beyond import Z
from ..theory.dimension import initial_temperature
# the closed forms, also this module's names (the callers of the old module path use them)
from ..theory.viscoelastic import (A1, A2, B1, C1, C2, EPS_HOLD, KAPPA, LOSS, P_LOSS, X_HOLD,
                                   asymptotic_temperature, cooling_rate_visco, free_cooling_temperature,
                                   late_slope_expansion, local_slope, loss_fraction, restitution, tau0)  # noqa: F401


# δ = 0 conserves energy to rounding: even 10^6 collisions per ensemble, each rounding the same way, drift
# by only 10^6 × 2^−52 ≈ 2e-10, while any real loss is of order δ
ELASTIC_TOL = 1e-9


# ----------------------------------------------------------------------------- rows
def run_delta(run):
    """δ of a run with the viscoelastic law (dsmc.restitution); ValueError naming the file otherwise."""
    law = run.config["dsmc"].get("restitution")
    if not law or law.get("law") != "viscoelastic":
        raise ValueError(f"{run.path}: not a viscoelastic run (dsmc.restitution = {law})")
    return float(law["delta"])


def log_spaced(M, count):
    """At most `count` observation indices 1…M, about evenly spaced in ln t (the grid is uniform in t)."""
    return np.unique(np.round(np.geomspace(1, M, count)).astype(int)) if M >= 1 else np.array([], int)


def viscoelastic_rows(runs, rows, late_from):
    """One row per (δ, observation time) at `rows` log-spaced times of each free-cooling run (read_run
    objects, any order): T with its half-width, the theory (the moment equation from T0 (1 − 1/n), the
    centred estimator's mean; for δ = 0 the run's own T(0), which elastic collisions conserve in every
    ensemble), T/theory − 1, the local slope from the previous row with its half-width and the theory's,
    a2, and `late` = 1 for the times t ≥ late_from of the slope fit (δ > 0)."""
    out = []
    for run in sorted(runs, key=run_delta):
        d, delta = run.config["dsmc"], run_delta(run)
        n, T0, g, C = int(d["particles"]), float(initial_temperature(d)), float(d["gamma"]), float(d["kernel"]["C"])
        dim = int(d.get("dimension", 3))
        idx = log_spaced(len(run.time) - 1, rows)
        t, T, ci = run.time[idx], run.temperature.mean[idx], run.temperature.ci[idx]
        th = (np.full(t.shape, run.temperature.mean[0]) if delta == 0
              else free_cooling_temperature(t, delta, T0 * (1 - 1 / n), g, C, n, dim))
        tau = tau0(delta, T0, g, C, n, dim)
        for k in range(len(idx)):
            row = {"delta": delta, "n": n, "N": int(run.config["ensembles"]), "t": float(t[k]),
                   "t_over_tau0": float(t[k] / tau), "T": float(T[k]), "ci": float(ci[k]), "T_theory": float(th[k]),
                   "rel_theory": float(T[k] / th[k] - 1), "slope": None, "slope_ci": None, "slope_theory": None,
                   "a2": float(run.a2.mean[idx[k]]), "a2_ci": float(run.a2.ci[idx[k]]),
                   "late": int(delta > 0 and t[k] >= late_from * (1 - 1e-12))}
            if k:
                span = math.log(t[k] / t[k - 1])
                row["slope"] = float(math.log(T[k] / T[k - 1]) / span)
                # any correlation between the two times: the half-widths add (triangle inequality)
                row["slope_ci"] = float((ci[k] / T[k] + ci[k - 1] / T[k - 1]) / span)
                row["slope_theory"] = float(math.log(th[k] / th[k - 1]) / span)
            out.append(row)
    return out


# ----------------------------------------------------------------------------- late slope, verdicts
def late_slope(rows):
    """Fit of ln T against ln t over the late rows of one δ, weighted by 1/(ci/T)²: the slope Σ c_i ln T_i,
    its half-width Σ|c_i| ci_i/T_i (valid whatever the correlation between the times, which the output does
    not give: the observations of one run share their ensembles), and the same fit of the theory."""
    late = [r for r in rows if r["late"]]
    if len(late) < 3:
        raise ValueError(f"δ = {rows[0]['delta'] if rows else '?'}: fewer than 3 late rows (late_from too close to t_end)")
    x = np.log([r["t"] for r in late])
    rel = np.array([r["ci"] / r["T"] for r in late])
    w = 1 / (rel / Z) ** 2
    xm = np.sum(w * x) / np.sum(w)
    c = w * (x - xm) / np.sum(w * (x - xm) ** 2)
    return {"value": float(c @ np.log([r["T"] for r in late])), "ci": float(np.abs(c) @ rel),
            "theory": float(c @ np.log([r["T_theory"] for r in late])), "t_min": late[0]["t"],
            "t_max": late[-1]["t"], "times": len(late)}


def slope_verdict(rows):
    """(ok, numbers, text) for the rows of one δ > 0.  The late slope s agrees with −5/3 when
    |s + 5/3| ≤ ci + allowance, allowance = approach + sonine: approach = |s_M + 5/3| with s_M the same fit
    of the moment equation (finite t/τ0 and the x² term of ε, module docstring); sonine = (5/3) KAPPA
    range(a2), the first-Sonine bound on what the Maxwellian theory leaves out (the cooling rate gains
    1 + KAPPA a2, which changes the late slope by −(5/3) KAPPA (a2(t) − ⟨a2⟩ over [0, t]); range over
    a2(0) = 0 and the rows).  Also requires Haff's −2 to be outside ci + allowance."""
    fit = late_slope(rows)
    a2 = [0.0] + [r["a2"] for r in rows]
    approach, sonine = abs(fit["theory"] + 5 / 3), 5 / 3 * KAPPA * (max(a2) - min(a2))
    band = fit["ci"] + approach + sonine
    agrees, haff = abs(fit["value"] + 5 / 3) <= band, abs(fit["value"] + 2) > band
    numbers = {**fit, "delta": rows[0]["delta"], "approach": approach, "sonine": sonine, "agrees": agrees,
               "haff_excluded": haff, "theory_agrees": abs(fit["value"] - fit["theory"]) <= fit["ci"] + sonine}
    word = "agrees with −5/3" if agrees else "differs from −5/3"
    text = (f"δ = {rows[0]['delta']:g}: late slope {fit['value']:.4f} ± {fit['ci']:.4f} (t ∈ [{fit['t_min']:g}, "
            f"{fit['t_max']:g}], {fit['times']} times) {word} within ci + allowance {approach + sonine:.4f} (approach "
            f"{approach:.4f}: the moment equation gives {fit['theory']:.4f}; first Sonine {sonine:.4f}); "
            + (f"Haff's −2 excluded ({abs(fit['value'] + 2):.2f} away)" if haff else "Haff's −2 NOT excluded"))
    return agrees and haff, numbers, text


def elastic_verdict(rows):
    """(ok, text) for the δ = 0 rows: T constant, |T/T(0) − 1| ≤ ELASTIC_TOL at every row."""
    worst = max(abs(r["rel_theory"]) for r in rows)
    ok = worst <= ELASTIC_TOL
    return ok, (f"δ = 0: T {'constant' if ok else 'NOT constant'} (max |T/T(0) − 1| = {worst:.1e} over "
                f"{len(rows)} times, t ≤ {rows[-1]['t']:g})")


def viscoelastic_verdict(rows):
    """(ok, per-δ numbers, text) over all rows: every δ > 0 by slope_verdict, δ = 0 by elastic_verdict."""
    ok, numbers, texts = True, [], []
    for delta in sorted({r["delta"] for r in rows}):
        mine = [r for r in rows if r["delta"] == delta]
        if delta == 0:
            good, text = elastic_verdict(mine)
        else:
            good, nums, text = slope_verdict(mine)
            numbers.append(nums)
        ok &= good
        texts.append(text)
    return ok, numbers, "; ".join(texts)


def short_verdict(ok, fits):
    """The report's one-line verdict: 'agrees: T ∝ t^(−5/3) (…)' or 'differs (…)', the late slope of each δ."""
    slopes = ", ".join(f"δ = {f['delta']:g}: {f['value']:.3f} ± {f['ci']:.3f}" for f in fits)
    haff = "Haff's −2 excluded" if all(f["haff_excluded"] for f in fits) else "Haff's −2 not excluded"
    return ("agrees: T ∝ t^(−5/3)" if ok else "differs") + f" (late slope {slopes}; {haff})"
