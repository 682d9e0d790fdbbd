"""Deep tails of GRW05 Examples 7-9 with weighted particles (SWPM) against constant weights.

A run's histogram (docs/output.md) holds per shell the fraction of the mass (constant weights: the
fraction of particles; SWPM: the summed weight, mean and confidence half-width over ensembles from
the exact sums at /accumulators/histogram_weight) and the particle count.  Both read alike
(local_exponent.shells_from_h5), so everything here works on either:

* shell_profile: f(r)/f(0) per shell (f = fraction / shell volume, f(0) from a fit to the core)
  with its relative confidence half-width (z = 3.2, the project's lambda_p);
* resolved_depth: the smallest f/f(0) of a shell whose relative half-width is below max_rel_ci
  (the goal: 30 %), and the radius of that shell;
* swpm_tail_summary: the depth, the local exponent b(r) far out (local_exponent.far_estimate), and
  the asymptotic b and a with confidence half-widths from one fit of ln f = c + chi ln r - a r^b
  (local_exponent.tail_fit, b free, chi free) on the pooled bins from f/f(0) < tail_from out to
  the depth: the fit the offset-free estimators of tails.md recommend.
"""
import numpy as np

from .local_exponent import Z, far_estimate, local_exponent, pool_shells, tail_fit
from .tail_local import shell_density
from ..theory.tail_theory import example_tail

SWPM_KEYS = ["example", "theory_b", "a_theory", "b_swpm", "b_swpm_ci", "a_swpm", "a_swpm_ci", "chi_swpm",
             "depth_swpm", "r_depth_swpm", "b_local_far_swpm", "b_local_far_swpm_ci", "r_far_swpm",
             "fit_r_lo", "fit_r_hi", "depth_constant", "r_depth_constant"]


def core_density(shells):
    """f(0) from the core: a weighted least-squares fit of ln f = c + d r^2 + e r^4 on the non-empty
    shells inside the mode of the fraction (about sqrt(2T)), weights fraction / se; returns e^c.
    The innermost shell alone is too small a volume to hold enough weight (often none with SWPM)."""
    r, f = shell_density(shells)
    k = max(int(np.argmax(shells["frac"])), 3) + 1
    sel = np.isfinite(f[:k]) & (shells["se"][:k] > 0)
    if sel.sum() < 3:
        raise ValueError(f"core of the histogram has {int(sel.sum())} usable shells, need >= 3")
    x, y, w = r[:k][sel], np.log(f[:k][sel]), shells["frac"][:k][sel] / shells["se"][:k][sel]
    A = np.stack([np.ones_like(x), x**2, x**4], axis=1)
    coef, *_ = np.linalg.lstsq(A * w[:, None], y * w, rcond=None)
    return float(np.exp(coef[0]))


def shell_profile(shells, z=Z):
    """(r_mid, ratio, rel_ci) per shell: f/f(0) (nan where empty; f(0) from core_density) and
    z * se / fraction."""
    r, f = shell_density(shells)
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.where(shells["frac"] > 0, z * shells["se"] / shells["frac"], np.inf)
    return r, f / core_density(shells), rel


def resolved_depth(shells, max_rel_ci=0.3, z=Z):
    """(depth, r): the smallest f/f(0) among the resolved shells (relative confidence half-width
    below max_rel_ci) of the contiguous resolved profile (inside resolved_limit), and the midpoint
    radius of that shell (nan, nan if none).  Contiguous: with few ensembles an isolated far shell
    can pass the test by chance (its ensembles' weights agreeing), which measures nothing."""
    r, ratio, rel = shell_profile(shells, z)
    inside = shells["edges"][1:] <= resolved_limit(shells, max_rel_ci, z) + 1e-12
    ok = (rel < max_rel_ci) & np.isfinite(ratio) & (ratio > 0) & inside
    if not ok.any():
        return float("nan"), float("nan")
    i = np.flatnonzero(ok)[np.argmin(ratio[ok])]
    return float(ratio[i]), float(r[i])


def resolved_limit(shells, max_rel_ci=0.3, z=Z):
    """The outer edge of the last shell, counted from the innermost, before the first shell whose
    relative half-width reaches max_rel_ci beyond the mode: where the resolved profile ends."""
    _, _, rel = shell_profile(shells, z)
    k0 = int(np.argmax(shells["frac"]))
    bad = ~(rel < max_rel_ci)
    bad[:k0] = False
    return float(shells["edges"][np.argmax(bad)]) if bad.any() else float(shells["edges"][-1])


def effective_counts(shells, z=Z):
    """A copy of shells whose counts are the effective sample sizes (fraction / se)^2 (0 where
    empty): the particle count for constant weights (Poisson), but for weighted particles the
    count that carries the same relative error, so that pooling (local_exponent.pool_shells,
    pool_min_count) gives bins of the same precision for both methods."""
    with np.errstate(divide="ignore", invalid="ignore"):
        eff = np.where(shells["se"] > 0, (shells["frac"] / shells["se"]) ** 2, 0.0)
    return {**shells, "counts": np.floor(np.nan_to_num(eff)).astype(np.int64)}


def swpm_tail_summary(shells, example, local, max_rel_ci=0.3, constant=None):
    """The numbers of one example (SWPM_KEYS) and the b(r) curve: (summary, curve).

    shells: local_exponent.shells_from_h5 of the SWPM run; local: config tails.local (pool_min_count,
    half_width, step, far_ci, tail_from); constant: the shells of the constant-weight run (its depth
    for comparison) or None.  The fit window runs from the first shell with f/f(0) < tail_from to
    resolved_limit (the resolved profile's end)."""
    theory = example_tail(example)
    pooled = pool_shells(effective_counts(shells), local["pool_min_count"])
    curve = local_exponent(pooled, half_width=local["half_width"], step=local["step"])
    try:
        far = far_estimate(curve, max_ci=local["far_ci"])
    except (ValueError, KeyError):  # no window measures b(r) to far_ci (KeyError: no window at all)
        far = {"r": float("nan"), "value": float("nan"), "ci": float("nan")}
    depth, r_depth = resolved_depth(shells, max_rel_ci)
    r, ratio, _ = shell_profile(shells)
    r_lo = float(r[np.argmax(np.nan_to_num(ratio, nan=1.0) < local["tail_from"])])
    r_hi = resolved_limit(shells, max_rel_ci)
    try:
        fit = tail_fit(pooled, r_lo, r_hi, chi_free=True, p0=[0.0, theory["a"], theory["b"], 0.0])
    except (ValueError, RuntimeError):  # too few resolved bins in the tail, or no convergence
        fit = {k: float("nan") for k in ("a", "b", "chi", "ci_a", "ci_b")}
    out = {"example": example, "theory_b": theory["b"], "a_theory": theory["a"], "b_swpm": fit["b"],
           "b_swpm_ci": fit["ci_b"], "a_swpm": fit["a"], "a_swpm_ci": fit["ci_a"], "chi_swpm": fit["chi"],
           "depth_swpm": depth, "r_depth_swpm": r_depth, "b_local_far_swpm": far["value"],
           "b_local_far_swpm_ci": far["ci"], "r_far_swpm": far["r"], "fit_r_lo": r_lo, "fit_r_hi": r_hi,
           "depth_constant": float("nan"), "r_depth_constant": float("nan")}
    if constant is not None:
        out["depth_constant"], out["r_depth_constant"] = resolved_depth(constant, max_rel_ci)
    return {k: int(v) if k == "example" else float(v) for k, v in out.items()}, curve


def swpm_kind(s, b_tol=0.03, ci_max=0.03, a_rel=0.05, depth_goal=1e-30, resolved_ci=0.1):
    """The report's outcome of a weighted-particle tail: 'agrees' where the goal is reached (the
    exponent b = 1 + lambda/2 is exact for the asymptotic tail); 'differs' where b is resolved (its
    half-width at most resolved_ci) and lies more than its half-width plus b_tol from the exact b;
    otherwise 'approximation': the run is too small to judge (the quick profile's)."""
    ok, _ = swpm_verdict(s, b_tol, ci_max, a_rel, depth_goal)
    if ok:
        return "agrees"
    resolved = bool(np.isfinite(s["b_swpm"]) and s["b_swpm_ci"] <= resolved_ci)
    if resolved and abs(s["b_swpm"] - s["theory_b"]) > s["b_swpm_ci"] + b_tol:
        return "differs"
    return "approximation"


def swpm_verdict(s, b_tol=0.03, ci_max=0.03, a_rel=0.05, depth_goal=1e-30):
    """(reached, text): the goal (the tail resolved to f/f(0) <= depth_goal, |b - theory| <=
    b_tol with half-width <= ci_max, and a within a_rel of theory) and how far the run got."""
    db, da = s["b_swpm"] - s["theory_b"], s["a_swpm"] / s["a_theory"] - 1
    ok = abs(db) <= b_tol and s["b_swpm_ci"] <= ci_max and abs(da) <= a_rel and s["depth_swpm"] <= depth_goal
    depth = (f"resolved to f/f(0) = {s['depth_swpm']:.1e} (constant weights {s['depth_constant']:.1e}; "
             f"goal {depth_goal:.0e})")
    if not np.isfinite(s["b_swpm"]):
        if s["fit_r_hi"] > s["fit_r_lo"]:  # a resolved tail, but (a, b, chi) together did not converge
            return False, (f"differs from the goal (b within {b_tol:g} of {s['theory_b']:g}): {depth}; on the "
                           f"resolved tail r = {s['fit_r_lo']:.3g}…{s['fit_r_hi']:.3g} the fit of a, b and χ "
                           "together does not converge (the window does not separate them)")
        return False, (f"differs from the goal (b within {b_tol:g} of {s['theory_b']:g}): {depth}, not below "
                       "tails.local.tail_from, so no tail to fit b and a on")
    text = (f"b = {s['b_swpm']:.3f} ± {s['b_swpm_ci']:.3f} (theory {s['theory_b']:g}), "
            f"a = {s['a_swpm']:.3f} ± {s['a_swpm_ci']:.3f} (theory {s['a_theory']:.3f}, {100 * da:+.0f} %), {depth}")
    return ok, ("agrees with the goal: " if ok else "differs from the goal: ") + text
