"""TV06 (Talbot, Viot, arXiv:cond-mat/0608158): reading the simulator's intruder and needle
outputs (docs/tv06.md), and the rows of the T/T_B tables (Figs. 3, 4), of the DSMC-against-
Gillespie table (§4) and of the needle table (Fig. 7, §3.2).
"""

import math

import numpy as np

from ..output.io import open_run, read_config, read_dataset, run_attrs
from ..theory import LAMBDA_P, exact_temperature_ratio, gaussian_temperature_ratio


# ----------------------------------------------------------------------------- simulator output
def _stat(f, name, path):
    out = {key: float(read_dataset(f, f"{name}/{key}", path)) for key in ("mean", "ci", "variance")}
    out["per_ensemble"] = read_dataset(f, f"{name}/per_ensemble", path).astype(float)
    if not all(map(math.isfinite, [out["mean"], out["ci"]])) or not np.all(np.isfinite(out["per_ensemble"])):
        raise ValueError(f"{path}: /{name} has non-finite values")
    return out


def _histogram(f, name):
    if name not in f:
        return None
    return {key: read_dataset(f, f"{name}/{key}") for key in ("edges", "counts", "density", "ci", "overflow")}


def read_tv06(path):
    """One TV06 run (model intruder or needle) as a dict: config, M, alpha, N, collisions,
    T_B, events, ns_per_collision (core time per collision, warm-up included) and
    intruder: bath, a, method, T (temperature_ratio: mean, ci, variance, per_ensemble), exact,
    histogram; needle: R, T_trans, T_rot, exact R, omega and velocity histograms."""
    with open_run(path) as f:
        config = read_config(f, path)
        model = config["model"]
        c = config[model]
        run = {"path": str(path), "model": model, "config": c, "M": float(c["mass"]), "alpha": float(c["alpha"]),
               "N": int(f.attrs["ensembles"]), "collisions": int(c["collisions"]),
               "T_B": float(read_dataset(f, "bath_temperature", path)),
               "events": {k: read_dataset(f, f"events/{k}", path) for k in f["events"]},
               **run_attrs(f)}
        threads = int(f["provenance"].attrs.get("threads", 1)) if "provenance" in f else 1
        total = run["N"] * (run["collisions"] + int(c.get("warmup", run["collisions"] // 10)))
        wall = run["wall_seconds"]
        run["ns_per_collision"] = None if wall is None else wall * min(threads, run["N"]) / total * 1e9
        if model == "intruder":
            exact = read_dataset(f, "exact/temperature_ratio", path) if "exact/temperature_ratio" in f else None
            run.update(bath=c["bath"]["kind"], a=float(c["bath"]["a"]), method=c.get("method", "gillespie"),
                       T=_stat(f, "temperature_ratio", path), exact=None if exact is None else float(exact),
                       histogram=_histogram(f, "histogram"))
        elif model == "needle":
            run.update(a=float(c.get("a", 1.0)), L=float(c.get("length", 1.0)), R=_stat(f, "R", path),
                       T_trans=_stat(f, "translational_temperature_ratio", path),
                       T_rot=_stat(f, "rotational_temperature_ratio", path),
                       R_exact=float(read_dataset(f, "exact/R", path)) if "exact/R" in f else None,
                       omega=_histogram(f, "omega_histogram"), velocity=_histogram(f, "velocity_histogram"))
        else:
            raise ValueError(f"{path}: model {model!r} is not a TV06 model")
    return run


# ----------------------------------------------------------------------------- Figs. 3, 4 and §4
TEMPERATURE_COLUMNS = ["bath", "method", "M", "alpha", "N", "collisions", "T_ratio", "ci", "exact", "deviation", "z",
                       "within_ci", "gaussian_eq18", "ensemble_min", "ensemble_median", "ensemble_max", "ensemble_sd",
                       "ns_per_collision"]


def temperature_row(run):
    """One row of the T/T_B tables: mean and ci over the N ensembles, the exact value where known
    (checked against the simulator's /exact), deviation, z = deviation / (ci / lambda_p), whether
    the exact value is within the ci, eq. (18) for reference, and the spread of the N values."""
    T, alpha, M = run["T"], run["alpha"], run["M"]
    exact = exact_temperature_ratio(run["bath"], alpha, M)
    if (exact is None) != (run["exact"] is None) or (exact is not None and abs(exact - run["exact"]) > 1e-12):
        raise ValueError(f"{run['path']}: /exact/temperature_ratio {run['exact']} differs from ours {exact}")
    dev = None if exact is None else T["mean"] - exact
    z = None if dev is None else (dev / (T["ci"] / LAMBDA_P) if T["ci"] > 0 else math.inf)
    per = T["per_ensemble"]
    return {"bath": run["bath"], "method": run["method"], "M": M, "alpha": alpha, "N": run["N"],
            "collisions": run["collisions"], "T_ratio": T["mean"], "ci": T["ci"], "exact": exact, "deviation": dev,
            "z": z, "within_ci": "" if dev is None else ("yes" if abs(dev) <= T["ci"] else "no"),
            "gaussian_eq18": float(gaussian_temperature_ratio(alpha, M)), "ensemble_min": float(per.min()),
            "ensemble_median": float(np.median(per)), "ensemble_max": float(per.max()),
            "ensemble_sd": float(per.std(ddof=1)) if per.size > 1 else None,
            "ns_per_collision": run["ns_per_collision"]}


def temperature_rows(runs):
    """Rows of the T/T_B table of Fig. 3 or 4, sorted by M (descending) and alpha."""
    return [temperature_row(r) for r in sorted(runs, key=lambda r: (-r["M"], r["alpha"]))]


DSMC_COLUMNS = ["M", "alpha", "N", "collisions", "exact", "T_gillespie", "ci_gillespie", "T_dsmc", "ci_dsmc",
                "difference", "joint_ci", "z_difference", "agree", "z_gillespie", "z_dsmc", "ns_gillespie", "ns_dsmc",
                "candidates_per_collision", "majorant_exceeded"]


def dsmc_rows(gillespie, dsmc):
    """§4: the Gillespie and DSMC intruders at the same (M, alpha), Gaussian bath: both T/T_B
    with ci, the exact eq. (18), their difference against the joint ci (hypot of the two) and the
    cost (core ns per collision; DSMC candidates per collision, majorant updates)."""
    by = {(r["M"], r["alpha"]): r for r in gillespie}
    rows = []
    for d in sorted(dsmc, key=lambda r: (r["M"], r["alpha"])):
        g = by.get((d["M"], d["alpha"]))
        if g is None:
            raise ValueError(f"{d['path']}: no Gillespie run at M = {d['M']}, alpha = {d['alpha']}")
        rg, rd = temperature_row(g), temperature_row(d)
        diff, joint = rd["T_ratio"] - rg["T_ratio"], math.hypot(rg["ci"], rd["ci"])
        ev = d["events"]
        cand = float(np.sum(ev["collisions"]) + np.sum(ev.get("fictitious", 0))) / float(np.sum(ev["collisions"]))
        rows.append({"M": d["M"], "alpha": d["alpha"], "N": d["N"], "collisions": d["collisions"],
                     "exact": rd["exact"], "T_gillespie": rg["T_ratio"], "ci_gillespie": rg["ci"],
                     "T_dsmc": rd["T_ratio"], "ci_dsmc": rd["ci"],
                     "difference": diff, "joint_ci": joint, "z_difference": diff / (joint / LAMBDA_P),
                     "agree": "yes" if abs(diff) <= joint else "no", "z_gillespie": rg["z"], "z_dsmc": rd["z"],
                     "ns_gillespie": rg["ns_per_collision"], "ns_dsmc": rd["ns_per_collision"],
                     "candidates_per_collision": cand,
                     "majorant_exceeded": int(np.sum(ev.get("majorant_exceeded", 0)))})
    return rows


# ----------------------------------------------------------------------------- Fig. 7, §3.2 (needle)
NEEDLE_COLUMNS = ["M", "alpha", "N", "collisions", "R", "R_ci", "R_exact", "R_z", "T_trans", "T_trans_ci", "T_rot",
                  "T_rot_ci", "trans_minus_rot", "trans_minus_rot_ci", "ordering", "ns_per_collision"]


def needle_rows(runs):
    """Fig. 7 and §3.2: R = <v^2 w^2>/(<v^2><w^2>) (eq. 30) with ci, R = 1 at alpha = 1 (z from
    it), T_trans/T_B and T_rot/T_B with ci, T_trans - T_rot with the ci of the per-ensemble
    differences, and the check of §3.2: 'T_B > T_trans > T_rot' when 1 - T_trans and T_trans -
    T_rot exceed their ci, 'equipartition' at alpha = 1 when both ratios are within ci of 1."""
    rows = []
    for r in sorted(runs, key=lambda r: (r["M"], r["alpha"])):
        R, tr, rot = r["R"], r["T_trans"], r["T_rot"]
        d = tr["per_ensemble"] - rot["per_ensemble"]
        d_ci = LAMBDA_P * float(d.std()) / math.sqrt(d.size)  # as the simulator's ci (1/N variance)
        R_exact = 1.0 if r["alpha"] == 1.0 else None
        if R_exact != r["R_exact"]:
            raise ValueError(f"{r['path']}: /exact/R is {r['R_exact']}, expected {R_exact}")
        if r["alpha"] == 1.0:
            equal = abs(tr["mean"] - 1) <= tr["ci"] and abs(rot["mean"] - 1) <= rot["ci"]
            ordering = "equipartition" if equal else "not equipartition"
        else:
            ordered = 1 - tr["mean"] > tr["ci"] and tr["mean"] - rot["mean"] > d_ci
            ordering = "T_B > T_trans > T_rot" if ordered else "not resolved"
        rows.append({"M": r["M"], "alpha": r["alpha"], "N": r["N"], "collisions": r["collisions"], "R": R["mean"],
                     "R_ci": R["ci"], "R_exact": R_exact,
                     "R_z": None if R_exact is None else (R["mean"] - 1) / (R["ci"] / LAMBDA_P),
                     "T_trans": tr["mean"], "T_trans_ci": tr["ci"], "T_rot": rot["mean"], "T_rot_ci": rot["ci"],
                     "trans_minus_rot": float(d.mean()), "trans_minus_rot_ci": d_ci, "ordering": ordering,
                     "ns_per_collision": r["ns_per_collision"]})
    return rows

