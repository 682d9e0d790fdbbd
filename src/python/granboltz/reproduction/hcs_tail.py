"""The exponential tail of the HCS of hard spheres measured deep with weighted particles (SWPM)
under the Gaussian thermostat: the fits of a run's pooled shells and the row verdict, against the
amplitude of granboltz.theory.hcs_tail (its names are also this module's).

The fits (on the pooled shells, each bin's f integrated over its shell as in
local_exponent.tail_fit, from the first shell with f/f(0) < tail_from out to the resolved end):

* the amplitude: ln f = c0 + chi ln c - A c (b = 1, the prefactor exponent chi free), A_swpm;
* the exponent: ln f = c0 - a c^b (b free, chi = 0), b_swpm.  With b and chi both free the two
  are nearly degenerate over a window of one decade in c (measured: b = 0.84-0.94 with a
  half-width of 0.14-0.7 on the quick runs), so b is fitted with chi = 0 and the first fit's chi
  shows whether that is fair (it is 0 within its interval on the runs measured).
"""

import numpy as np
from scipy.optimize import curve_fit

from ..analysis.local_exponent import Z, log_bin_model, shell_quadrature, pool_shells, tail_fit
from ..analysis.tail_swpm import effective_counts, resolved_depth, resolved_limit, shell_profile
# the closed forms, also this module's names (the callers of the old module path use them)
from ..theory.hcs_tail import (hcs_amplitude, maxwellian_cooling_rate, sonine_cooling_rate, thermal_speed)  # noqa: F401


HCS_TAIL_COLUMNS = ["alpha", "b_swpm", "b_swpm_ci", "A_swpm", "A_theory", "depth_swpm"]


def exponential_fit(pooled, r_lo, r_hi, v0, z=Z):
    """The fit ln f = c0 + chi ln c - A c (b = 1) of the pooled bins inside [r_lo, r_hi], c = r/v0:
    dict A, chi and their ci (z se from the covariance), bins."""
    sel = (pooled["lo"] >= r_lo) & (pooled["hi"] <= r_hi)
    if sel.sum() < 5:
        raise ValueError(f"window [{r_lo}, {r_hi}] holds {int(sel.sum())} pooled bins, need >= 5")
    frac = pooled["frac"][sel]
    r, logw = shell_quadrature(pooled["lo"][sel], pooled["hi"][sel])
    model, jac = log_bin_model(r, logw, True)  # in r: a = A/v0; chi in r and in c differ by a constant

    def m(x, c, a, chi):
        return model(x, c, a, 1.0, chi)

    def j(x, c, a, chi):
        return jac(x, c, a, 1.0, chi)[:, [0, 1, 3]]
    rm = 0.5 * (pooled["lo"][sel] + pooled["hi"][sel])
    dens = frac / (4 / 3 * np.pi * (pooled["hi"][sel] ** 3 - pooled["lo"][sel] ** 3))
    slope, icpt = np.polyfit(rm, np.log(dens), 1)
    popt, pcov = curve_fit(m, None, np.log(frac), p0=[icpt, max(-slope, 1e-3), 0.0],
                           sigma=pooled["se"][sel] / frac, jac=j, absolute_sigma=True,
                           bounds=([-np.inf, 1e-12, -50.0], [np.inf, np.inf, 50.0]), method="trf",
                           x_scale="jac", ftol=1e-12, xtol=1e-12, gtol=1e-12, max_nfev=400)
    se = np.sqrt(np.diag(pcov))
    return {"A": float(popt[1] * v0), "A_ci": float(z * se[1] * v0), "chi": float(popt[2]),
            "chi_ci": float(z * se[2]), "bins": int(sel.sum())}


def hcs_tail_summary(shells, alpha, zeta, gamma, C, T, local, max_rel_ci=0.3, d=3):
    """One row of the table (HCS_TAIL_COLUMNS) plus the fits' details (chi, the intervals, the
    window).

    shells: local_exponent.shells_from_h5(..., steady=True) of the SWPM run; zeta its
    /steady/cooling_rate/mean; local: pool_min_count and tail_from."""
    v0 = thermal_speed(T)
    A_theory = hcs_amplitude(zeta, gamma, C, T, d=d)
    pooled = pool_shells(effective_counts(shells), local["pool_min_count"])
    depth, r_depth = resolved_depth(shells, max_rel_ci)
    r, ratio, _ = shell_profile(shells)
    r_lo = float(r[np.argmax(np.nan_to_num(ratio, nan=1.0) < local["tail_from"])])
    r_hi = resolved_limit(shells, max_rel_ci)
    nan = float("nan")
    try:
        fb = tail_fit(pooled, r_lo, r_hi, chi_free=False, p0=[0.0, A_theory / v0, 1.0])
    except (ValueError, RuntimeError):  # too few resolved bins in the tail, or no convergence
        fb = {"b": nan, "ci_b": nan}
    try:
        fa = exponential_fit(pooled, r_lo, r_hi, v0)
    except (ValueError, RuntimeError):
        fa = {"A": nan, "A_ci": nan, "chi": nan, "chi_ci": nan}
    return {"alpha": float(alpha), "b_swpm": float(fb["b"]), "b_swpm_ci": float(fb["ci_b"]),
            "A_swpm": fa["A"], "A_theory": float(A_theory), "depth_swpm": float(depth),
            "A_swpm_ci": fa["A_ci"], "chi_swpm": fa["chi"], "chi_swpm_ci": fa["chi_ci"], "zeta": float(zeta),
            "r_depth_swpm": float(r_depth), "fit_r_lo": r_lo, "fit_r_hi": float(r_hi)}


def hcs_tail_row_verdict(row, b_tol=0.03, A_rel=0.05, depth_goal=1e-20):
    """(ok, text) of one row: |b - 1| <= b_tol, |A/A_theory - 1| <= A_rel, depth <= depth_goal."""
    b, A, At, depth = (float(row[k]) for k in ("b_swpm", "A_swpm", "A_theory", "depth_swpm"))
    dA = A / At - 1.0
    ok = bool(np.isfinite(b) and abs(b - 1.0) <= b_tol and abs(dA) <= A_rel and depth <= depth_goal)
    text = (f"α = {float(row['alpha']):g}: b = {b:.3f} ± {float(row['b_swpm_ci']):.3f} (theory 1), "
            f"A = {A:.3f} against 8πγC v0/ζ = {At:.3f} ({100 * dA:+.1f} %), depth {depth:.1e}")
    return ok, text
