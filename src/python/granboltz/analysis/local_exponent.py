r"""Local tail exponents from shell histograms, free of the core's offset.

GRW05's eq. (38) fits ln(ln f_k0 - ln f_k), which carries the offset C' between the core and the
tail (granboltz.theory.tail_theory).  The estimators here only use ln f up to an additive constant:

* local_exponent: the logarithmic-derivative exponent b(r) = 1 + d ln(-d_r ln f)/d ln r.  A second
  derivative of the log of noisy counts is not differenced directly: on a sliding window of pooled
  shells we fit the family ln f = c - A r^B, whose exponent b(r) is the constant B, so the fit
  matches ln f and its first two derivatives at the window's centre and B estimates b(r) there
  (a Savitzky-Golay smoothing within the family that contains the answer).
* sliding_tail_fit / tail_fit: ln f = c + chi ln r - a r^b with chi free (4 parameters; needs a
  wider window: chi ln r and r^b differ only in the third derivative).

Pooling: adjacent shells are merged until a pooled bin holds min_count particles (relative error
~1/sqrt(min_count)), so each ln F_j has a small, nearly Gaussian error and no empty bins; bins stay
one shell wide where data are plentiful and widen in the tail.  The model is integrated over each
bin (F_j = int 4 pi r^2 f dr, Gauss-Legendre in log-sum-exp form), so wide bins of a steeply
falling f bias nothing.  Fits are weighted least squares on ln F_j with var(ln F_j) =
sum_k se_k^2 / F_j^2 (se_k: the standard error of shell k's fraction over the N ensembles).
Bands: the delta method (the fit's covariance; shells independent), or with per-ensemble counts a
grouped jackknife over ensembles.  Half-widths are z * standard error (z = 3.2: lambda_p of GRW05
§5.1, p = 0.999, as every other ci of the project).
"""
import h5py
import numpy as np
import yaml
from scipy.optimize import curve_fit
from scipy.special import logsumexp

from ..theory import LAMBDA_P

Z = LAMBDA_P
_NODES, _WEIGHTS = np.polynomial.legendre.leggauss(12)


def shells_from_h5(path, row=-1, steady=False):
    """Shell data of a granboltz run at observation `row` (docs/output.md /histogram): dict edges
    [K+1], frac [K] (fraction per shell, overflow dropped), se [K] (= ci / lambda_p), counts [K]
    (all ensembles), N, n.  steady=True: the steady-state histogram /steady/histogram instead (each
    ensemble's time average over t_m > steady_from), counts summed over those times."""
    with h5py.File(path, "r") as f:
        lam = float(f.attrs["confidence_lambda_p"])
        config = f.attrs["config"]
        config = yaml.safe_load(config.decode() if isinstance(config, bytes) else str(config))
        out = {"edges": f["histogram/edges"][()], "N": int(f.attrs["ensembles"]), "n": int(config["dsmc"]["particles"])}
        if steady:
            if "steady/histogram" not in f:
                raise KeyError(f"{path}: no /steady/histogram (the run has no dsmc.steady_from)")
            t, start = f["time"][()], float(config["dsmc"]["steady_from"])
            # the simulator's steady rows; with dsmc.observe (no observe_every) exactly t > steady_from
            rows = t > start + 1e-9 * float(config["dsmc"].get("observe_every") or 0.0)
            return {**out, "frac": f["steady/histogram/mean"][:-1], "se": f["steady/histogram/ci"][:-1] / lam,
                    "counts": f["histogram/counts"][rows, :-1].sum(axis=0)}
        return {**out, "frac": f["histogram/mean"][row, :-1], "se": f["histogram/ci"][row, :-1] / lam,
                "counts": f["histogram/counts"][row, :-1]}


def shells_from_ensembles(edges, counts):
    """Shell data from per-ensemble shell counts [N, K] (each row: one ensemble of n particles,
    n = row sum including any overflow the caller left in): frac, se, counts, N, per_ensemble."""
    counts = np.asarray(counts)
    n = counts.sum(axis=1, keepdims=True)
    per = counts / n
    N = per.shape[0]
    return {"edges": np.asarray(edges, float), "frac": per.mean(axis=0), "se": per.std(axis=0, ddof=1) / np.sqrt(N),
            "counts": counts.sum(axis=0), "N": N, "per_ensemble": per}


def data_limit(shells, min_count=10, max_rel_ci=0.5, z=Z, start=None):
    """Radius where the data run out: the inner edge of the first shell beyond the mode of the
    fraction (or beyond `start`) with fewer than min_count particles or a relative confidence
    half-width z*se/frac above max_rel_ci (the outer edge R if none)."""
    frac, se, counts, edges = shells["frac"], shells["se"], shells["counts"], shells["edges"]
    k0 = int(np.argmax(frac)) if start is None else int(np.searchsorted(edges, start, side="right") - 1)
    with np.errstate(divide="ignore", invalid="ignore"):
        bad = (counts < min_count) | ~(z * se / frac <= max_rel_ci)
    bad[:k0] = False
    return float(edges[np.argmax(bad)]) if bad.any() else float(edges[-1])


def pool_shells(shells, min_count=400):
    """Merge adjacent shells (inside out) until each bin holds >= min_count particles; the last,
    incomplete bin and everything after the first empty shell are dropped.  Returns dict lo, hi
    (radii), frac, se, counts, slices (shell index ranges) and, if present, per_ensemble [N, J]."""
    counts, edges = shells["counts"], shells["edges"]
    stop = int(np.argmax(counts == 0)) if (counts == 0).any() else len(counts)
    groups, start, acc = [], 0, 0
    for k in range(stop):
        acc += counts[k]
        if acc >= min_count:
            groups.append((start, k + 1))
            start, acc = k + 1, 0
    pooled = {"lo": np.array([edges[a] for a, _ in groups]), "hi": np.array([edges[b] for _, b in groups]),
              "frac": np.array([shells["frac"][a:b].sum() for a, b in groups]),
              "se": np.array([np.sqrt(np.sum(shells["se"][a:b] ** 2)) for a, b in groups]),
              "counts": np.array([counts[a:b].sum() for a, b in groups]), "slices": groups}
    if "per_ensemble" in shells:  # then the pooled se includes the shells' covariances
        per = np.stack([shells["per_ensemble"][:, a:b].sum(axis=1) for a, b in groups], axis=1)
        pooled["per_ensemble"], pooled["se"] = per, per.std(axis=0, ddof=1) / np.sqrt(per.shape[0])
    return pooled


def shell_quadrature(lo, hi):
    """Gauss-Legendre nodes r and log weights (with the shell volume 4 pi r^2, d = 3) over each shell [lo, hi]."""
    r = 0.5 * (hi - lo)[:, None] * _NODES + 0.5 * (hi + lo)[:, None]
    return r, np.log(0.5 * (hi - lo)[:, None] * _WEIGHTS * 4 * np.pi * r**2)


def log_bin_model(r, logw, chi_free):
    """ln F_j(c, a, b[, chi]) = c + ln sum_i w_ij r_ij^chi exp(-a r_ij^b) and its Jacobian (the
    derivatives are averages over the nodes with the softmax weights of the integrand)."""
    lr = np.log(r)

    def parts(c, a, b, chi):
        rb = r**b
        e = logw + chi * lr - a * rb
        lse = logsumexp(e, axis=1)
        return lse, np.exp(e - lse[:, None]), rb

    def model(_, c, a, b, chi=0.0):
        return c + parts(c, a, b, chi)[0]

    def jac(_, c, a, b, chi=0.0):
        _, w, rb = parts(c, a, b, chi)
        cols = [np.ones(len(r)), -np.sum(w * rb, axis=1), -a * np.sum(w * rb * lr, axis=1)]
        return np.stack(cols + [np.sum(w * lr, axis=1)] * chi_free, axis=1)
    if chi_free:
        return model, jac
    return (lambda x, c, a, b: model(x, c, a, b)), (lambda x, c, a, b: jac(x, c, a, b))


def _fit(pooled, sel, chi_free, p0, frac=None):
    frac = pooled["frac"][sel] if frac is None else frac[sel]
    r, logw = shell_quadrature(pooled["lo"][sel], pooled["hi"][sel])
    sigma = pooled["se"][sel] / pooled["frac"][sel]
    lower, upper = [-np.inf, 1e-12, 0.05] + [-50.0] * chi_free, [np.inf, np.inf, 5.0] + [50.0] * chi_free
    model, jac = log_bin_model(r, logw, chi_free)
    popt, pcov = curve_fit(model, None, np.log(frac), p0=p0, sigma=sigma, jac=jac,
                           absolute_sigma=True, bounds=(lower, upper), method="trf", x_scale="jac",
                           ftol=1e-12, xtol=1e-12, gtol=1e-12, max_nfev=400)
    return popt, pcov


def _start(pooled, sel, chi_free):
    rm = 0.5 * (pooled["lo"][sel] + pooled["hi"][sel])
    dens = pooled["frac"][sel] / (4 / 3 * np.pi * (pooled["hi"][sel] ** 3 - pooled["lo"][sel] ** 3))
    slope, icpt = np.polyfit(rm, np.log(dens), 1)
    return [icpt, max(-slope, 1e-3), 1.0] + [0.0] * chi_free


def tail_fit(pooled, r_lo, r_hi, chi_free=True, z=Z, jackknife_groups=0, p0=None):
    """Weighted least-squares fit of ln f = c + chi ln r - a r^b (chi = 0 unless chi_free) to the
    pooled bins inside [r_lo, r_hi]: dict c, a, b, chi (values), se_* and ci_* (z * se), r (the
    count-weighted mean radius of the window), bins.  se from the fit's covariance, or from a
    grouped jackknife over ensembles when jackknife_groups > 1 and per-ensemble data exist;
    at_bound: b or chi ended on its bound (the window does not constrain it; its ci means nothing)."""
    sel = (pooled["lo"] >= r_lo) & (pooled["hi"] <= r_hi)
    npar = 4 if chi_free else 3
    if sel.sum() < npar + 2:
        raise ValueError(f"window [{r_lo}, {r_hi}] holds {int(sel.sum())} pooled bins, need >= {npar + 2}")
    popt, pcov = _fit(pooled, sel, chi_free, _start(pooled, sel, chi_free) if p0 is None else p0)
    se = np.sqrt(np.diag(pcov))
    if jackknife_groups > 1 and "per_ensemble" in pooled:
        per = pooled["per_ensemble"]
        groups = np.array_split(np.arange(per.shape[0]), jackknife_groups)
        reps = np.array([_fit(pooled, sel, chi_free, popt, np.delete(per, g, axis=0).mean(axis=0))[0] for g in groups])
        G = len(groups)
        se = np.sqrt((G - 1) / G * np.sum((reps - reps.mean(axis=0)) ** 2, axis=0))
    names = ["c", "a", "b", "chi"][:npar]
    rm = 0.5 * (pooled["lo"][sel] + pooled["hi"][sel])
    out = {"r": float(np.average(rm, weights=pooled["counts"][sel])), "bins": int(sel.sum())}
    for i, name in enumerate(names):
        out[name], out["se_" + name], out["ci_" + name] = float(popt[i]), float(se[i]), float(z * se[i])
    out.setdefault("chi", 0.0)
    # a parameter on its bound (b in [0.05, 5], |chi| <= 50) means the window does not constrain it
    out["at_bound"] = bool(popt[2] <= 0.0501 or popt[2] >= 4.99 or (chi_free and abs(popt[3]) >= 49.9))
    return out


def _sliding(pooled, half_width, chi_free, z, jackknife_groups, step):
    J, rows = len(pooled["frac"]), []
    for j in range(half_width, J - half_width, step):
        lo, hi = pooled["lo"][j - half_width], pooled["hi"][j + half_width]
        try:
            rows.append(tail_fit(pooled, lo, hi, chi_free, z, jackknife_groups))
        except RuntimeError:  # curve_fit did not converge: the window is left out
            continue
    return {key: np.array([row[key] for row in rows]) for key in (rows[0] if rows else [])}


def local_exponent(pooled, half_width=4, z=Z, jackknife_groups=0, step=1):
    """b(r) = 1 + d ln(-d_r ln f)/d ln r on sliding windows of 2*half_width+1 pooled bins (fit of
    ln f = c - A r^B, module docstring), centred on every step-th bin: dict of arrays r, b, se_b,
    ci_b, a, c, ..., at_bound (see tail_fit)."""
    return _sliding(pooled, half_width, False, z, jackknife_groups, step)


def sliding_tail_fit(pooled, half_width=8, z=Z, jackknife_groups=0, step=1):
    """Sliding-window fits of ln f = c + chi ln r - a r^b with chi free: dict of arrays r, a, b,
    chi, se_*, ci_*, at_bound (one entry per window of 2*half_width+1 pooled bins, every step-th).
    Far out the bands get wide and the delta method is only indicative (far from Gaussian)."""
    return _sliding(pooled, half_width, True, z, jackknife_groups, step)


def far_estimate(result, max_ci=0.15, key="b"):
    """The outermost window of a local_exponent / sliding_tail_fit result whose band half-width
    ci_<key> is at most max_ci (and not at a bound): dict r, value, ci (how far the data measure
    the exponent to +-max_ci).  ValueError if no window qualifies."""
    ok = (result["ci_" + key] <= max_ci) & ~result["at_bound"]
    if not ok.any():
        raise ValueError(f"no window measures {key} to +-{max_ci}")
    i = np.flatnonzero(ok)[-1]
    return {"r": float(result["r"][i]), "value": float(result[key][i]), "ci": float(result["ci_" + key][i])}
