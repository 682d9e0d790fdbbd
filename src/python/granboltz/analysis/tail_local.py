"""The local-exponent analysis of one GRW05 tail example (Examples 7-9).

local_tail_summary joins granboltz.analysis.local_exponent (b(r) with its band, how far the data reach)
and granboltz.theory.tail_theory (a, b to leading order; the eq. 38 slope a given core offset implies):

* b_local_far +- b_local_far_ci at r_far: b(r) at the outermost window whose band half-width is
  at most far_ci; f_ratio_far = f(r_far)/f(0) and r_far_thermal = r_far / sqrt(T);
* a_fit, chi_fit, offset: weighted least squares of ln f = c + chi ln r - a r^b with b fixed at
  theory, on the pooled bins with f/f(0) < tail_from inside the data limit (linear in c, chi, a;
  f at the bin midpoint); offset C' = ln f_k0 - c - as in ln f_k0 - ln f = a r^b - chi ln r + C';
* b_local_expected: b(r_far) of that fitted tail, 1 + d ln(a b r^(b-1) - chi/r)/d ln r: the prefactor
  r^chi makes b(r) approach b only like chi/(a b r^b), so this, not b, is what b(r) should show;
* b_eq38_expected: the slope GRW05's eq. (38) fit would give on a window of x = ln(k - k0) for
  that tail (tail_theory.eq38_slope), to set against the measured one.
local_verdict states whether b(r) is consistent with theory where the data reach.
"""
import numpy as np

from .local_exponent import Z, data_limit, far_estimate, local_exponent, pool_shells
from ..theory.tail_theory import eq38_slope, example_tail

SUMMARY_KEYS = ["example", "lambda", "theory_b", "a_theory", "b_local_far", "b_local_far_ci", "r_far",
                "r_far_thermal", "f_ratio_far", "r_limit", "a_fit", "a_fit_ci", "chi_fit", "offset", "b_local_expected",
                "b_eq38_expected", "b_eq38_expected_paper"]


def shell_density(shells):
    """(r_mid, f) per shell: the fraction divided by the shell volume (nan where empty)."""
    e = shells["edges"]
    f = shells["frac"] / (4.0 * np.pi / 3.0 * (e[1:] ** 3 - e[:-1] ** 3))
    return 0.5 * (e[1:] + e[:-1]), np.where(f > 0, f, np.nan)


def model_local_exponent(a, b, chi, r):
    """b(r) = 1 + d ln(-d_r ln f)/d ln r of f = r^chi exp(-a r^b): 1 + (a b (b-1) r^(b-1) + chi/r) /
    (a b r^(b-1) - chi/r) (tends to b like chi/(a b r^b))."""
    r = np.asarray(r, dtype=float)
    g = a * b * r ** (b - 1) - chi / r
    return 1.0 + (a * b * (b - 1) * r ** (b - 1) + chi / r) / g


def fixed_exponent_fit(pooled, b, r_lo, r_hi, z=Z):
    """Weighted least squares of ln f = c + chi ln r - a r^b (b fixed) on the pooled bins inside
    [r_lo, r_hi], f the bin's mean density at its midpoint: dict c, chi, a, ci_a (z * se), bins."""
    sel = (pooled["lo"] >= r_lo) & (pooled["hi"] <= r_hi)
    if sel.sum() < 4:
        raise ValueError(f"[{r_lo:g}, {r_hi:g}] holds {int(sel.sum())} pooled bins, need >= 4")
    lo, hi = pooled["lo"][sel], pooled["hi"][sel]
    r = 0.5 * (lo + hi)
    y = np.log(pooled["frac"][sel] / (4.0 * np.pi / 3.0 * (hi**3 - lo**3)))
    w = pooled["frac"][sel] / pooled["se"][sel]  # 1 / sd of ln F
    A = np.stack([np.ones_like(r), np.log(r), -(r**b)], axis=1)
    coef, *_ = np.linalg.lstsq(A * w[:, None], y * w, rcond=None)
    cov = np.linalg.inv((A * w[:, None]).T @ (A * w[:, None]))
    return {"c": float(coef[0]), "chi": float(coef[1]), "a": float(coef[2]),
            "ci_a": float(z * np.sqrt(cov[2, 2])), "bins": int(sel.sum())}


def local_tail_summary(shells, T, lam, example, local, fit_window, k0=1):
    """The numbers of one example (SUMMARY_KEYS) and the b(r) curve: (summary, curve).
    shells: local_exponent.shells_from_h5; T: the final temperature; local: config tails.local."""
    theory = example_tail(example)
    if abs(theory["b"] - (1 + lam / 2)) > 1e-12:
        raise ValueError(f"Example {example}: run lambda = {lam} is not the example's")
    pooled = pool_shells(shells, local["pool_min_count"])
    curve = local_exponent(pooled, half_width=local["half_width"], step=local["step"])
    far = far_estimate(curve, max_ci=local["far_ci"])
    r_limit = data_limit(shells)
    r_mid, f = shell_density(shells)
    ok = np.isfinite(f)
    f0 = f[k0 - 1]
    ratio_far = float(np.exp(np.interp(far["r"], r_mid[ok], np.log(f[ok])))) / f0
    r_tail = float(r_mid[ok][np.argmax(f[ok] / f0 < local["tail_from"])])
    fit = fixed_exponent_fit(pooled, theory["b"], r_tail, r_limit)
    offset = float(np.log(f0) - fit["c"])
    R, K = float(shells["edges"][-1]), len(shells["frac"])
    expected = [eq38_slope(fit["a"], theory["b"], offset, R, K, k0, w, fit["chi"])
                for w in (fit_window, local["paper_window"])]
    summary = {"example": example, "lambda": lam, "theory_b": theory["b"], "a_theory": theory["a"],
               "b_local_far": far["value"], "b_local_far_ci": far["ci"], "r_far": far["r"],
               "r_far_thermal": far["r"] / np.sqrt(T), "f_ratio_far": ratio_far, "r_limit": r_limit,
               "a_fit": fit["a"], "a_fit_ci": fit["ci_a"], "chi_fit": fit["chi"], "offset": offset,
               "b_local_expected": float(model_local_exponent(fit["a"], theory["b"], fit["chi"], far["r"])),
               "b_eq38_expected": expected[0], "b_eq38_expected_paper": expected[1]}
    return {k: float(v) if k != "example" else int(v) for k, v in summary.items()}, curve


def window_radii(window, radius, shells, k0=1):
    """The r-interval [r_lo, r_hi] (shell midpoints) of an eq. (38) window of x = ln(k - k0)."""
    k_lo, k_hi = np.ceil(np.exp(window[0]) - 1e-9) + k0, np.floor(np.exp(window[1]) + 1e-9) + k0
    h = radius / shells
    return float((k_lo - 0.5) * h), float((k_hi - 0.5) * h)


def local_verdict(s):
    """Short verdict of one example from its summary: 'agrees' if the band of b_local_far holds
    the theory b or b_local_expected (the theory tail with its fitted prefactor r^chi), else
    'differs'; with how far out the data measure b(r) and the expected eq. (38) slope."""
    ci, b, th, bx = s["b_local_far_ci"], s["b_local_far"], s["theory_b"], s["b_local_expected"]
    where = (f"b(r) = {b:.3f} ± {ci:.3f} at r = {s['r_far']:.3g} "
             f"({s['r_far_thermal']:.2g} thermal speeds, f/f(0) = {s['f_ratio_far']:.1e})")
    rest = (f"; a = {s['a_fit']:.3f} ± {s['a_fit_ci']:.3f} at b = {th:g} (theory {s['a_theory']:.3f}); "
            f"eq. (38) expected {s['b_eq38_expected']:.3f} given C′ = {s['offset']:.2f}")
    if abs(b - th) <= ci:
        how = "inside the band"
    elif abs(b - bx) <= ci:
        how = f"with prefactor r^{s['chi_fit']:.2f}: b(r) → {th:g} slowly, {bx:.3f} expected at r_far"
    else:
        return f"differs: not consistent with b = {th:g} where the data reach ({bx:.3f} expected): {where}{rest}"
    return f"agrees: consistent with b = {th:g} where the data reach ({how}): {where}{rest}"
