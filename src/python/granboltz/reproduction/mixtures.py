"""Beyond the papers: binary mixtures of inelastic hard spheres and disks: the correlation of the
steady T1, T2, the table rows and the verdict of the report item (rule beyond_mixture,
docs/workflow.md), against the temperature ratios of granboltz.theory.mixtures (its names are
also this module's).
"""

import numpy as np

from ..theory.dimension import dsmc_geometry
# the closed forms, also this module's names (the callers of the old module path use them)
from ..theory.mixtures import (hcs_temperature_ratios, martin_piasecki, partial_cooling_rates,
                               temperature_ratio, white_noise_temperature_ratios)  # noqa: F401


def mixture_correlation(s1, s2, s_mix, x1, x2):
    """The correlation of the steady T1 and T2 estimates, recovered from the mixture's steady
    temperature T = x1 T1 + x2 T2 of the same samples: Var T = x1^2 s1^2 + x2^2 s2^2 + 2 x1 x2 cov
    holds exactly for any estimator linear in the samples (the ensembles' time averages, or the
    samples taken as independent); clipped to [-1, 1] against rounding.  The Gaussian thermostat
    holds T, so it is close to -1 there: ignoring it (rho = 0) would make the ratio's interval
    too narrow, not conservative."""
    if s1 == 0 or s2 == 0:
        return 0.0
    cov = (s_mix**2 - (x1 * s1) ** 2 - (x2 * s2) ** 2) / (2 * x1 * x2)
    return float(np.clip(cov / (s1 * s2), -1.0, 1.0))


def mixture_rows(runs):
    """One row per steady binary-mixture run (read_run objects with dsmc.species of two species,
    the first the heavier): mass_ratio = m1/m2, alpha, T1/T2 with its half-width (the simulator's
    /steady/temperature_ratio/<1>_over_<2>: the ratio of the steady averages, its interval by the
    delta method with the measured covariance of T1 and T2 over the ensembles; granboltz.output.ratios),
    Garzó-Dufty's T1/T2 for the thermostat, x1, the diameters and d of the run, difference =
    ours/GD - 1 (relative, with sign), and the correlation of the steady T1 and T2
    (mixture_correlation).  ValueError naming the file for a run without the stored ratio (a
    simulator that did not store it: rerun)."""
    rows = []
    for run in runs:
        d = run.config["dsmc"]
        if len(run.species) != 2:
            raise ValueError(f"{run.path}: not a binary mixture (dsmc.species with two species)")
        (n1, sp1), (n2, sp2) = run.species.items()
        th = d.get("thermostat", "white_noise")
        alpha = d["alpha"]
        if not isinstance(alpha, (int, float)):
            raise ValueError(f"{run.path}: the table needs one alpha for every pair")
        key = f"temperature_ratio/{n1}_over_{n2}"
        if key not in run.steady:
            raise ValueError(f"{run.path}: no /steady/{key} (a simulator older than the stored ratios): rerun it")
        t1, t2, tm, r = sp1.steady["temperature"], sp2.steady["temperature"], run.steady["temperature"], run.steady[key]
        rho = mixture_correlation(float(t1.sigma), float(t2.sigma), float(tm.sigma), sp1.fraction, sp2.fraction)
        x1 = sp1.fraction  # N1/n, the fraction the run has
        dim, geometry = dsmc_geometry(d)
        gd = temperature_ratio(th, sp1.mass / sp2.mass, alpha, x1, sp1.diameter / sp2.diameter, dim, geometry)
        value = float(r.mean)
        rows.append({"mass_ratio": sp1.mass / sp2.mass, "alpha": float(alpha), "t1_t2": value, "t1_t2_ci": float(r.ci),
                     "t1_t2_garzo_dufty": gd, "difference": value / gd - 1, "thermostat": th, "x1": x1,
                     "n": int(d["particles"]), "N": int(run.config["ensembles"]),
                     "T1": float(t1.mean), "T1_ci": float(t1.ci), "T2": float(t2.mean), "T2_ci": float(t2.ci),
                     "correlation": rho, "species": f"{n1}/{n2}", "d": dim})
    return sorted(rows, key=lambda r: (r["mass_ratio"], -r["alpha"]))


def mixture_verdict(rows, mild=0.8):
    """(ours, short) texts over the rows of mixture_rows: the measured relative differences from
    Garzó-Dufty, overall and at alpha >= mild (where the Maxwellian approximation is known to be
    good); whether each lies outside its interval.  A comparison with an approximation, never a
    failure: the short text says 'compared with an approximation (Maxwellian), differs by X %'."""
    if not rows:
        return "no runs", "no runs"
    worst = max(rows, key=lambda r: abs(r["difference"]))
    near = [r for r in rows if r["alpha"] >= mild]
    parts = []
    for m in sorted({r["mass_ratio"] for r in rows}):
        mine = [r for r in rows if r["mass_ratio"] == m]
        cells = ", ".join(f"{r['alpha']:g}: {r['t1_t2']:.4f} ± {r['t1_t2_ci']:.4f} vs {r['t1_t2_garzo_dufty']:.4f} "
                          f"({r['difference']:+.2%})" for r in mine)
        parts.append(f"m1/m2 = {m:g}: α {cells}")
    resolved = sum(abs(r["t1_t2"] - r["t1_t2_garzo_dufty"]) > r["t1_t2_ci"] for r in rows)
    near_text = (f"; at α ≥ {mild:g} at most {max(abs(r['difference']) for r in near):.2%}" if near else "")
    ours = (f"T1/T2 of the HCS compared with the Maxwellian approximation of Garzó–Dufty: differs by at most "
            f"{abs(worst['difference']):.2%} (m1/m2 = {worst['mass_ratio']:g}, α = {worst['alpha']:g}){near_text}; "
            f"{resolved} of {len(rows)} differences exceed the interval; " + "; ".join(parts))
    near_worst = max(near, key=lambda r: abs(r["difference"])) if near else None
    short = (f"compared with an approximation (Maxwellian Garzó–Dufty), differs by up to {worst['difference']:+.1%}"
             + (f" ({near_worst['difference']:+.1%} at α ≥ {mild:g})" if near else ""))
    return ours, short
