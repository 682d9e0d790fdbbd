"""Report sections of TV06: T/T_B against the exact values (Figs. 3, 4), the needle (Fig. 7,
§3.2) and DSMC against Gillespie (§4)."""

import numpy as np

from .numbers import DASH, LAMBDA_P, fl, num, pm, verdict


# ----------------------------------------------------------------------------- TV06 comparisons
def _tv06_size(ours):
    return f"N = {ours[0]['N']} ensembles × {int(fl(ours[0]['collisions']))} collisions per point"


def compare_tv06_temperature(name, ours, published=None, **_):
    """TV06 Figs. 3, 4: T/T_B per (M, alpha) with its ci, against the exact value where one is
    known (eq. 18 for the Gaussian bath; alpha at M = alpha for any bath); eq. (18) alongside."""
    header = ["bath", "M", "α", "T/T_B ± CI", "exact", "ours − exact", "verdict", "eq. (18), Gaussian bath",
              "single ensembles (min … max)"]
    rows, zs = [], []
    powerlaw = any(r["bath"] == "powerlaw" for r in ours)
    for r in ours:
        z = fl(r["z"])
        if z is not None:
            zs.append(z)
        rows.append([r["bath"], num(fl(r["M"])), num(fl(r["alpha"])), pm(fl(r["T_ratio"]), fl(r["ci"]), 5),
                     num(fl(r["exact"]), 5), DASH if z is None else f"{fl(r['deviation']):+.5f} ({z:+.1f}σ)",
                     DASH if z is None else verdict(abs(z)) + (" (indicative CI)" if powerlaw else ""),
                     num(fl(r["gaussian_eq18"]), 5),
                     f"{num(fl(r['ensemble_min']), 4)} … {num(fl(r['ensemble_max']), 4)}"])
    text = [f"{_tv06_size(ours)}; CI = 3.2 × the standard error over the ensembles (the simulator's ci). With "
            f"N = {ours[0]['N']} estimated variances (normalised by N) an interval covers its expectation with "
            "probability P(|t_(N−1)| ≤ 3.2·√((N−1)/N)) (0.986 for N = 10), not 0.999."]
    inside = sum(abs(z) <= LAMBDA_P for z in zs)
    if powerlaw:
        text.append("Power-law bath: v1² has infinite variance (the v⁻⁴ tails), so these CIs assume what does not "
                    "hold and undercover, mostly with the mean below the truth (docs/tv06.md: 4.7 % of repeated "
                    "runs beyond 3.2 standard errors instead of 0.14 %); the σ-distances are indicative only. "
                    "Fig. 5 checks the exact M = α solution bin by bin with valid intervals.")
        short = "; ".join(f"M = α = {num(fl(r['alpha']))}: {fl(r['z']):+.1f}σ from the exact α" for r in ours
                          if fl(r["z"]) is not None) + " (nominal CIs, indicative: infinite variance)"
    else:
        worst = max(abs(z) for z in zs) if zs else float("nan")
        short = (("agrees" if inside == len(zs) else f"{len(zs) - inside} point(s) outside the CI")
                 + f": {inside}/{len(zs)} points within the CI of eq. (18) (max {worst:.1f}σ)")
    return [("table", header, rows), ("ul", text)], short


def compare_tv06_needle(name, ours, published=None, **_):
    """TV06 Fig. 7 and §3.2: R with ci (R = 1 at alpha = 1), T_trans/T_B, T_rot/T_B and the check
    T_B > T_trans > T_rot of §3.2 for alpha < 1, point by point."""
    header = ["M", "α", "R ± CI", "R vs 1 (α = 1)", "T_trans/T_B ± CI", "T_rot/T_B ± CI", "T_trans − T_rot ± CI",
              "§3.2 check"]
    rows = [[num(fl(r["M"])), num(fl(r["alpha"])), pm(fl(r["R"]), fl(r["R_ci"]), 5),
             DASH if fl(r["R_z"]) is None else verdict(abs(fl(r["R_z"]))),
             pm(fl(r["T_trans"]), fl(r["T_trans_ci"]), 4),
             pm(fl(r["T_rot"]), fl(r["T_rot_ci"]), 4), pm(fl(r["trans_minus_rot"]), fl(r["trans_minus_rot_ci"]), 3),
             r["ordering"]] for r in ours]
    elastic = [r for r in ours if fl(r["R_z"]) is not None]
    ok_R = sum(abs(fl(r["R_z"])) <= LAMBDA_P for r in elastic)
    inelastic = [r for r in ours if fl(r["alpha"]) < 1]
    ordered = sum(r["ordering"] == "T_B > T_trans > T_rot" for r in inelastic)
    text = [f"{_tv06_size(ours)}; T_trans = M⟨|v|²⟩/2 (per degree of freedom), T_rot = I⟨ω²⟩, I = ML²/12, "
            "T_B = 1/(2a); the CI of T_trans − T_rot is over the per-ensemble differences (the two come from the "
            "same runs).",
            "§3.2 check: 'T_B > T_trans > T_rot' when 1 − T_trans/T_B and T_trans − T_rot both exceed their CI; "
            "'equipartition' at α = 1 when both ratios are within their CI of 1."]
    good = ok_R == len(elastic) and ordered == len(inelastic)
    short = (("agrees" if good else "check") + f": R = 1 within CI at α = 1 ({ok_R}/{len(elastic)}); "
             f"T_B > T_trans > T_rot at {ordered}/{len(inelastic)} points with α < 1")
    return [("table", header, rows), ("ul", text)], short


def compare_tv06_dsmc(name, ours, published=None, **_):
    """TV06 §4: DSMC and Gillespie T/T_B side by side with the exact eq. (18); verdict from the
    joint ci of the difference; cost per collision."""
    header = ["M", "α", "exact, eq. (18)", "Gillespie ± CI", "DSMC ± CI", "DSMC − Gillespie", "verdict",
              "vs exact (Gillespie; DSMC)", "ns per collision (Gillespie; DSMC)", "DSMC candidates per collision"]
    rows, zs = [], []
    for r in ours:
        z = fl(r["z_difference"])
        zs.append(abs(z))
        rows.append([num(fl(r["M"])), num(fl(r["alpha"])), num(fl(r["exact"]), 5),
                     pm(fl(r["T_gillespie"]), fl(r["ci_gillespie"]), 5), pm(fl(r["T_dsmc"]), fl(r["ci_dsmc"]), 5),
                     pm(fl(r["difference"]), fl(r["joint_ci"]), 2), verdict(abs(z)),
                     f"{fl(r['z_gillespie']):+.1f}σ; {fl(r['z_dsmc']):+.1f}σ",
                     f"{num(fl(r['ns_gillespie']))}; {num(fl(r['ns_dsmc']))}", num(fl(r["candidates_per_collision"]))])
    text = [f"{_tv06_size(ours)} and method, independent seeds; joint CI = hypot(CI_G, CI_D). DSMC (§4): "
            "n_bath bath particles, every tested particle redrawn from f (the paper does not say how the bath stays "
            "thermalized; docs/tv06.md), ω_max raised when exceeded as in the paper.",
            "Cost: core time per collision, warm-up included, from the simulator's wall time and threads (noisy on "
            "a shared machine); the DSMC tests "
            f"{np.mean([fl(r['candidates_per_collision']) for r in ours]):.1f} candidates per collision on average."]
    agree = sum(z <= LAMBDA_P for z in zs)
    short = (("agrees" if agree == len(zs) else f"{len(zs) - agree} point(s) differ")
             + f": DSMC = Gillespie within the joint CI at {agree}/{len(zs)} points (max {max(zs):.1f}σ)")
    return [("table", header, rows), ("ul", text)], short
