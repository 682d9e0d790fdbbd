"""TV06 histograms (Figs. 5 and 8): rebinning, the folded |v1| tail on logarithmic bins and its
exponent, a bin-by-bin check against an exact density, and the Gaussian fits of the needle's
omega distribution.
"""

import math

import numpy as np
from scipy import stats

from ..theory import LAMBDA_P


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
