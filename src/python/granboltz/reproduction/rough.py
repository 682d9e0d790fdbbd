"""Beyond the papers: rough inelastic hard spheres (d = 3) and disks (d = 2): the table rows and the
verdict of the report item (rule beyond_rough), against theta = T_rot/T_tr of
granboltz.theory.rough (its names are also this module's).
"""

import numpy as np

from ..theory.dimension import run_geometry
# the closed forms, also this module's names (the callers of the old module path use them)
from ..theory.rough import (KAPPA_DISK, KAPPA_SPHERE, coefficients, hcs_theta, temperature_rates, theta,
                            white_noise_theta)  # noqa: F401


def rough_rows(runs):
    """One row per steady rough-particle run (read_run objects with dsmc.roughness, hard spheres or
    disks: kernel.lambda 1): thermostat, alpha, beta, kappa, d, theta = T_rot/T_tr with its half-width
    (the simulator's /steady/theta: the ratio of the steady averages, its interval by the delta
    method with the measured covariance of T_rot and T_tr over the ensembles; granboltz.output.ratios),
    the Maxwellian theta of the run's d and difference = ours/Maxwellian - 1.  ValueError naming
    the file for a run without roughness, of another kernel, or without /steady/theta (made by a
    simulator that did not store it: rerun)."""
    rows = []
    for run in runs:
        d = run.config["dsmc"]
        rough = d.get("roughness")
        if not isinstance(rough, dict):
            raise ValueError(f"{run.path}: not a rough-sphere run (no dsmc.roughness)")
        if float(d["kernel"]["lambda"]) != 1:
            raise ValueError(f"{run.path}: the Maxwellian theta is of hard spheres and disks (kernel.lambda 1), "
                             f"not lambda = {d['kernel']['lambda']}")
        if "theta" not in run.steady:
            raise ValueError(f"{run.path}: no /steady/theta (a simulator older than the stored ratios): rerun it")
        th_name, alpha = d.get("thermostat", "white_noise"), float(d["alpha"])
        beta, kappa = float(rough["beta"]), float(rough["inertia"])
        dim, geometry = run_geometry(run)
        rot, tr, th = run.steady["temperature_rotational"], run.steady["temperature"], run.steady["theta"]
        ref = float(theta(th_name, alpha, beta, kappa, dim, geometry))
        value = float(th.mean)
        rows.append({"thermostat": th_name, "alpha": alpha, "beta": beta, "theta": value, "theta_ci": float(th.ci),
                     "theta_maxwellian": ref, "difference": value / ref - 1, "kappa": kappa,
                     "n": int(d["particles"]), "N": int(run.config["ensembles"]),
                     "T_tr": float(tr.mean), "T_rot": float(rot.mean), "d": dim})
    return sorted(rows, key=lambda r: (r["d"], r["thermostat"], -r["alpha"], r["beta"]))


def rough_verdict(rows):
    """(ours, short) texts over the rows of rough_rows, per d and thermostat: the range of the measured
    relative differences from the Maxwellian theta and how many exceed their interval.  A
    comparison with an approximation, never a failure (beyond.md §5 expects the HCS theta 4-5 %
    below the formula at alpha = 0.8-0.9 and white noise within 1 %)."""
    if not rows:
        return "no runs", "no runs"
    names = {"gaussian": "HCS", "white_noise": "white noise"}
    ours, short = [], []
    for dim, th in ((d, t) for d in (3, 2) for t in ("gaussian", "white_noise")):
        mine = [r for r in rows if r["thermostat"] == th and int(r.get("d", 3)) == dim]
        if not mine:
            continue
        lo, hi = min(r["difference"] for r in mine), max(r["difference"] for r in mine)
        out = sum(abs(r["theta"] - r["theta_maxwellian"]) > r["theta_ci"] for r in mine)
        cells = ", ".join(f"α {r['alpha']:g} β {r['beta']:g}: {r['theta']:.4f} ± {r['theta_ci']:.4f} vs "
                          f"{r['theta_maxwellian']:.4f} ({r['difference']:+.2%})" for r in mine)
        span = f"{lo:+.1%}" if np.isclose(lo, hi, atol=5e-4) else f"{lo:+.1%} to {hi:+.1%}"
        name = names[th] + ("" if dim == 3 else " (disks)")
        ours.append(f"{name}: differs by {span} ({out} of {len(mine)} outside the interval; {cells})")
        short.append(f"{name} {span}")
    return ("θ = T_rot/T_tr compared with the Maxwellian approximation (Huthmann–Zippelius): " + "; ".join(ours),
            "compared with an approximation (Maxwellian), differs by " + ", ".join(short))
