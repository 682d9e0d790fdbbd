"""The tail analysis of GRW05 §5.3: the points of eq. (38) from a radial histogram, the
least-squares exponent b on a window of x, and the tail-exponent and window tables.
"""

import math

import numpy as np


def shell_measure(edges, dimension=3):
    """The measure of the velocity shells r_{k-1} <= |v| < r_k of a radial histogram in d
    dimensions: 4 pi (r_k^3 - r_{k-1}^3)/3 (d = 3) or pi (r_k^2 - r_{k-1}^2) (d = 2). A shell's
    fraction over it estimates f at |v| = r_k."""
    edges = np.asarray(edges, float)
    if dimension == 2:
        return math.pi * (edges[1:] ** 2 - edges[:-1] ** 2)
    if dimension == 3:
        return 4.0 * math.pi / 3.0 * (edges[1:] ** 3 - edges[:-1] ** 3)
    raise ValueError(f"dimension must be 2 or 3, not {dimension!r}")


# ----------------------------------------------------------------------------- GRW05 §5.3 tails
def kernel_name(lam):
    """The kernel's name in the published tail table."""
    return {0.0: "maxwell", 1.0: "hard_spheres"}.get(float(lam), "vhs")


def tail_points(hist, k0, min_count, histogram="density", row=-1):
    """(k, x_k, y_k) of GRW05 eq. (38) from the histogram at observation `row` (default: last).

    Shells are 1-based as in the paper (f_1: |v| < r_1); x_k = ln(k - k0) (the shell index: the
    same slope as ln(r_k - r_k0), since r_k = k h), y_k = ln(ln f_k0 - ln f_k), k > k0.
    histogram = "density": f_k is the fraction of eq. (37) divided by the shell volume
    4 pi (r_k^3 - r_{k-1}^3) / 3, an estimate of f_inf(r_k) as eq. (38) models it; "fraction":
    the fraction itself (then y_k is undefined wherever f_k >= f_k0, i.e. below the shell where
    the r^2-weighted fraction falls under f_k0). Skipped: the overflow shell, shells with fewer
    than min_count particles (over all ensembles) and shells with f_k >= f_k0.
    """
    f, counts = hist["mean"][row, :-1], hist["counts"][row, :-1]
    if histogram == "density":
        edges = hist["edges"]
        f = f / shell_measure(edges, 3)
    elif histogram != "fraction":
        raise ValueError(f"histogram must be density or fraction, not {histogram!r}")
    if counts[k0 - 1] < min_count or f[k0 - 1] <= 0:
        raise ValueError(f"reference shell k0 = {k0} is empty")
    k = np.arange(1, f.size + 1)
    keep = (k > k0) & (counts >= min_count) & (f > 0) & (f < f[k0 - 1])
    return k[keep], np.log(k[keep] - k0), np.log(np.log(f[k0 - 1]) - np.log(f[keep]))


def fit_tail(x, y, window):
    """Least-squares line y = c + b x on window[0] <= x <= window[1] (scipy linregress): dict
    b, b_stderr, intercept, points (nan with fewer than 3 points)."""
    from scipy import stats

    x, y = np.asarray(x, float), np.asarray(y, float)
    sel = (x >= window[0]) & (x <= window[1])
    if sel.sum() < 3:
        return {"b": float("nan"), "b_stderr": float("nan"), "intercept": float("nan"), "points": int(sel.sum())}
    fit = stats.linregress(x[sel], y[sel])
    return {"b": float(fit.slope), "b_stderr": float(fit.stderr), "intercept": float(fit.intercept),
            "points": int(sel.sum())}


TAIL_COLUMNS = ["example", "kernel", "lambda", "theory_b", "b", "b_stderr", "fit_window",
                "x_variable", "histogram", "k0", "points", "intercept", "R", "t_end", "n", "N"]
# From the local-exponent analysis (granboltz.analysis.tail_local, one summary per example).
LOCAL_COLUMNS = ["b_local_far", "b_local_far_ci", "r_far", "a_fit", "a_theory", "a_fit_ci", "chi_fit",
                 "r_far_thermal", "f_ratio_far", "r_limit", "b_local_expected", "offset", "b_eq38_expected"]
# From the weighted-particle runs (granboltz.analysis.tail_swpm, one summary per example).
SWPM_COLUMNS = ["b_swpm", "b_swpm_ci", "a_swpm", "a_swpm_ci", "depth_swpm", "depth_constant"]
WINDOW_COLUMNS = ["example", "lambda", "histogram", "window", "k_minus_k0", "points", "b", "b_stderr", "theory_b"]


def window_text(window):
    """A fit window as printed in the tables: "[lo, hi]"."""
    return f"[{window[0]:g}, {window[1]:g}]"


def tail_rows(hists, tails, local=None, swpm=None):
    """The tail-exponent table (one row per example: the fit on tails["fit_window"] with
    tails["histogram"]) and the window table (every example on every window of tails["windows"],
    for both histogram normalisations). hists: {example number: read_histogram dict}; theory_b =
    1 + lambda/2 (GRW05 eqs. 20, 21); local: {example: tail_local summary} adds LOCAL_COLUMNS;
    swpm: {example: tail_swpm summary} adds SWPM_COLUMNS."""
    rows, wrows = [], []
    for ex, hist in sorted(hists.items()):
        d = hist["config"]["dsmc"]
        lam = float(d["kernel"]["lambda"])
        _, x, y = tail_points(hist, tails["k0"], tails["min_count"], tails["histogram"])
        fit = fit_tail(x, y, tails["fit_window"])
        rows.append({"example": ex, "kernel": kernel_name(lam), "lambda": lam, "theory_b": 1 + lam / 2,
                     "fit_window": window_text(tails["fit_window"]), "x_variable": "ln(k-k0)",
                     "histogram": tails["histogram"], "k0": tails["k0"], "R": d["histogram"]["radius"],
                     "t_end": d["t_end"], "n": hist["n"], "N": hist["N"], **fit})
        if local is not None:
            rows[-1].update({key: local[ex][key] for key in LOCAL_COLUMNS})
        if swpm is not None:
            rows[-1].update({key: swpm[ex][key] for key in SWPM_COLUMNS})
        for histogram in ("density", "fraction"):
            _, x, y = tail_points(hist, tails["k0"], tails["min_count"], histogram)
            for w in tails["windows"]:
                lo, hi = math.ceil(math.exp(w[0]) - 1e-9), math.floor(math.exp(w[1]) + 1e-9)
                wrows.append({"example": ex, "lambda": lam, "histogram": histogram, "window": window_text(w),
                              "k_minus_k0": f"{lo}-{hi}", "theory_b": 1 + lam / 2, **fit_tail(x, y, w)})
    return rows, wrows

