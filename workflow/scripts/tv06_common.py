"""TV06 (Talbot, Viot, arXiv:cond-mat/0608158): the analytic formulas of §3.1, reading the
simulator's intruder and needle outputs (docs/tv06.md), and the numbers behind every TV06 figure
and table (Figs. 1-5, 7, 8, §3.2, §4). Shared by the workflow scripts tv06_*.py and the tests;
plain functions of paths and values, never the `snakemake` object.

Equation numbers are those of the pdf text (`…pdf-text.txt`, as docs/tv06.md); the html text
numbers g_± as eqs. 14-15 and eqs. 15-19 of the pdf as 19-23. Bath particles have m = 1.
"""

import math

import h5py
import numpy as np
import yaml
from scipy import integrate, special, stats

import granboltz_common as gc

LAMBDA_P = gc.LAMBDA_P  # the simulator's ci = 3.2 sqrt(variance / N)


# ----------------------------------------------------------------------------- analytic (§3.1)
def gaussian_pdf(v, a):
    """Gaussian bath f(v, a) = sqrt(a/pi) exp(-a v^2), eq. (14); T_B = <v^2> = 1/(2a)."""
    return np.sqrt(a / np.pi) * np.exp(-a * np.asarray(v, float) ** 2)


def powerlaw_pdf(v, a):
    """Power-law bath f(v, a) = sqrt(2a)/pi / (1 + a^2 v^4), eq. (19); T_B = <v^2> = 1/a."""
    return math.sqrt(2.0 * a) / np.pi / (1.0 + a**2 * np.asarray(v, float) ** 4)


def gaussian_fluxes(v1, a, rho=1.0):
    """Collision rates (phi_+, phi_-, phi) of an intruder moving at v1 in the Gaussian bath,
    eqs. (15)-(16): phi_± = rho/2 (±v1 + exp(-a v1^2)/sqrt(pi a) + v1 erf(v1 sqrt(a))),
    phi = phi_+ + phi_-. Written with erfc (v1 (1 ± erf x) = v1 erfc(∓x)), the same functions
    without the cancellation of (15) in the rate of the trailing side at large |v1|."""
    v1 = np.asarray(v1, float)
    e, x = np.exp(-a * v1**2) / np.sqrt(np.pi * a), v1 * np.sqrt(a)
    plus, minus = rho / 2 * (e + v1 * special.erfc(-x)), rho / 2 * (e - v1 * special.erfc(x))
    return plus, minus, plus + minus


def fluxes_by_quadrature(v1, a, rho=1.0):
    """(phi_+, phi_-) of eqs. (5)-(6) by numerical quadrature (scipy quad), for checking (15)."""
    plus = integrate.quad(lambda v: (v1 - v) * gaussian_pdf(v, a), -np.inf, v1, epsabs=1e-14, epsrel=1e-13)[0]
    minus = integrate.quad(lambda v: (v - v1) * gaussian_pdf(v, a), v1, np.inf, epsabs=1e-14, epsrel=1e-13)[0]
    return rho * plus, rho * minus


def colliding_density(v, v1, a, rho=1.0, side=+1):
    """Density of the velocity v of the bath particle hitting an intruder moving at v1, Gaussian
    bath: g_+ = rho (v1 - v) f(v) / phi_+(v1) for v <= v1 (eq. 12), g_- = rho (v - v1) f(v) /
    phi_-(v1) for v >= v1 (eq. 13). (The paper prints them without rho, i.e. for rho = 1; with
    it they integrate to 1 for any rho.)"""
    v = np.asarray(v, float)
    plus, minus, _ = gaussian_fluxes(v1, a, rho)
    if side > 0:
        return np.where(v <= v1, rho * (v1 - v) * gaussian_pdf(v, a) / plus, 0.0)
    return np.where(v >= v1, rho * (v - v1) * gaussian_pdf(v, a) / minus, 0.0)


def colliding_mass(v1, a, lo, hi, side=+1):
    """Probability that the colliding velocity of eqs. (12)/(13) lies in [lo, hi] (quadrature)."""
    lo, hi = (max(lo, v1), hi) if side < 0 else (lo, min(hi, v1))
    if hi <= lo:
        return 0.0
    return integrate.quad(lambda v: float(colliding_density(v, v1, a, side=side)), lo, hi, epsabs=1e-15)[0]


def gaussian_temperature_ratio(alpha, M):
    """T/T_B of the intruder in a Gaussian bath (Martin and Piasecki), eq. (18):
    (1 + alpha) / (2 + (1 - alpha)/M)."""
    alpha = np.asarray(alpha, float)
    return (1.0 + alpha) / (2.0 + (1.0 - alpha) / M)


def exact_temperature_ratio(bath, alpha, M):
    """The exact T/T_B where one is known: eq. (18) for the Gaussian bath; alpha at M = alpha for
    any bath (eq. 17: the intruder takes the colliding velocity, its distribution is f itself,
    so T = M <v^2> = alpha T_B); None otherwise."""
    if bath == "gaussian":
        return float(gaussian_temperature_ratio(alpha, M))
    return float(alpha) if math.isclose(alpha, M, rel_tol=1e-12) else None


def t_coverage(N, lambda_p=LAMBDA_P):
    """Probability that the mean of N normal values lies within the simulator's ci of its
    expectation, ci = lambda_p sqrt(var/N) with var the variance over the ensembles (1/N
    normalisation): P(|t_{N-1}| <= lambda_p sqrt((N-1)/N)) (0.986 for N = 10, 0.9986 as N grows)."""
    return float(1.0 - 2.0 * stats.t.sf(lambda_p * math.sqrt((N - 1) / N), N - 1)) if N > 1 else float("nan")


# ----------------------------------------------------------------------------- simulator output
def _stat(f, name, path):
    out = {key: float(f[f"{name}/{key}"][()]) for key in ("mean", "ci", "variance")}
    out["per_ensemble"] = f[f"{name}/per_ensemble"][()].astype(float)
    if not all(map(math.isfinite, [out["mean"], out["ci"]])) or not np.all(np.isfinite(out["per_ensemble"])):
        raise ValueError(f"{path}: /{name} has non-finite values")
    return out


def _histogram(f, name):
    if name not in f:
        return None
    return {key: f[f"{name}/{key}"][()] for key in ("edges", "counts", "density", "ci", "overflow")}


def read_tv06(path):
    """One TV06 run (model intruder or needle) as a dict: config, M, alpha, N, collisions,
    T_B, events, ns_per_collision (core time per collision, warm-up included) and
    intruder: bath, a, method, T (temperature_ratio: mean, ci, variance, per_ensemble), exact,
    histogram; needle: R, T_trans, T_rot, exact R, omega and velocity histograms."""
    with h5py.File(path, "r") as f:
        config = yaml.safe_load(gc._text(f.attrs["config"]))
        model = config["model"]
        c = config[model]
        run = {"path": str(path), "model": model, "config": c, "M": float(c["mass"]), "alpha": float(c["alpha"]),
               "N": int(f.attrs["ensembles"]), "collisions": int(c["collisions"]),
               "T_B": float(f["bath_temperature"][()]), "events": {k: f["events"][k][()] for k in f["events"]},
               **gc.run_attrs(f)}
        threads = int(f["provenance"].attrs.get("threads", 1)) if "provenance" in f else 1
        total = run["N"] * (run["collisions"] + int(c.get("warmup", run["collisions"] // 10)))
        wall = run["wall_seconds"]
        run["ns_per_collision"] = None if wall is None else wall * min(threads, run["N"]) / total * 1e9
        if model == "intruder":
            exact = f["exact/temperature_ratio"][()] if "exact/temperature_ratio" in f else None
            run.update(bath=c["bath"]["kind"], a=float(c["bath"]["a"]), method=c.get("method", "gillespie"),
                       T=_stat(f, "temperature_ratio", path), exact=None if exact is None else float(exact),
                       histogram=_histogram(f, "histogram"))
        elif model == "needle":
            run.update(a=float(c.get("a", 1.0)), L=float(c.get("length", 1.0)), R=_stat(f, "R", path),
                       T_trans=_stat(f, "translational_temperature_ratio", path),
                       T_rot=_stat(f, "rotational_temperature_ratio", path),
                       R_exact=float(f["exact/R"][()]) if "exact/R" in f else None,
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


# ----------------------------------------------------------------------------- Fig. 5 (histograms)
def rebin(hist, factor):
    """(centres, density, ci) of a v1 histogram with `factor` neighbouring bins merged (density
    as the simulator's, counts / (all samples x width); ci combined as for independent bins:
    for display only)."""
    edges, density, ci = hist["edges"], hist["density"], hist["ci"]
    n = (density.size // factor) * factor
    d = density[:n].reshape(-1, factor).mean(axis=1)
    c = np.sqrt((ci[:n].reshape(-1, factor) ** 2).sum(axis=1)) / factor
    e = edges[: n + 1 : factor]
    return 0.5 * (e[1:] + e[:-1]), d, c


def folded_tail(hist, v_min, bins_per_decade=8):
    """Density of |v1| on logarithmic bins from v_min to the histogram range (both signs pooled,
    per unit v on one side: counts / (all samples x 2 x width)); the log-bin bounds are moved to
    the simulator's bin edges, so the rebinning is exact. Returns (v, density, counts), v the
    geometric centre of each bin; empty bins are dropped."""
    edges, counts = hist["edges"], hist["counts"].astype(float)
    total = counts.sum() + float(np.sum(hist["overflow"]))
    h, top = edges[1] - edges[0], edges[-1]
    n = max(1, math.ceil(math.log10(top / v_min) * bins_per_decade))
    bounds = np.unique(np.round(np.geomspace(v_min, top, n + 1) / h) * h)
    speed = np.abs(0.5 * (edges[1:] + edges[:-1]))
    idx = np.searchsorted(bounds, speed, side="right") - 1
    ok = (idx >= 0) & (idx < bounds.size - 1)
    sums = np.bincount(idx[ok], weights=counts[ok], minlength=bounds.size - 1)
    density = sums / (total * 2.0 * np.diff(bounds))
    keep = sums > 0
    return np.sqrt(bounds[:-1] * bounds[1:])[keep], density[keep], sums[keep]


def tail_exponent(v, density, counts, window, min_count=10):
    """Least-squares slope of ln density against ln v on window[0] <= v <= window[1] (bins with
    at least min_count samples): dict exponent, stderr, points (nan with fewer than 3 points)."""
    sel = (v >= window[0]) & (v <= window[1]) & (counts >= min_count)
    if sel.sum() < 3:
        return {"exponent": float("nan"), "stderr": float("nan"), "points": int(sel.sum())}
    fit = stats.linregress(np.log(v[sel]), np.log(density[sel]))
    return {"exponent": float(fit.slope), "stderr": float(fit.stderr), "points": int(sel.sum())}


def bin_average(pdf, edges):
    """Average of pdf over each bin (Simpson's rule), to compare with a histogram density."""
    lo, hi = edges[:-1], edges[1:]
    return (pdf(lo) + 4.0 * pdf(0.5 * (lo + hi)) + pdf(hi)) / 6.0


def histogram_check(hist, pdf, v_max, N, min_count=20):
    """Histogram against an exact density on |v| <= v_max: bins whose ci contains the exact bin
    average, and the largest |z| = |density - exact| / (ci / lambda_p). Only bins with at least
    min_count samples per ensemble (N ensembles) count: in sparser bins the per-ensemble counts
    are far from normal (mostly 0 or 1) and the ci means little."""
    edges, density, ci = hist["edges"], hist["density"], hist["ci"]
    centre = 0.5 * (edges[1:] + edges[:-1])
    sel = (np.abs(centre) <= v_max) & (ci > 0) & (hist["counts"] >= min_count * N)
    dev = density[sel] - bin_average(pdf, edges)[sel]
    return {"bins": int(sel.sum()), "within": int(np.sum(np.abs(dev) <= ci[sel])),
            "max_z": float(np.max(np.abs(dev) / (ci[sel] / LAMBDA_P))) if sel.any() else float("nan")}


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


# ----------------------------------------------------------------------------- Fig. 8
def gaussian_fits(hist):
    """Two Gaussians for an omega histogram: 'moments', the normal density with the histogram's
    variance (overflow excluded); 'fit', A exp(-w^2 / (2 s^2)) fitted by unweighted least squares
    to the density (scipy.optimize.curve_fit). Returns dict with s_moments, s_fit, A_fit, the
    excess kurtosis of the histogram and both curves at the bin centres."""
    from scipy.optimize import curve_fit

    edges, density, counts = hist["edges"], hist["density"], hist["counts"].astype(float)
    w = 0.5 * (edges[1:] + edges[:-1])
    m2 = float(np.sum(counts * w**2) / counts.sum())
    m4 = float(np.sum(counts * w**4) / counts.sum())
    s_mom = math.sqrt(m2)

    def gauss(x, A, s):
        return A * np.exp(-(x**2) / (2.0 * s**2))

    (A, s), _ = curve_fit(gauss, w, density, p0=(1.0 / (s_mom * math.sqrt(2 * math.pi)), s_mom))
    return {"centres": w, "s_moments": s_mom, "s_fit": abs(float(s)), "A_fit": float(A),
            "excess_kurtosis": m4 / m2**2 - 3.0, "moments": np.exp(-(w**2) / (2 * m2)) / math.sqrt(2 * math.pi * m2),
            "fit": gauss(w, A, s)}
