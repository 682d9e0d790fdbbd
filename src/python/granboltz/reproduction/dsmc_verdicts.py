"""GRW05 and RW05: the texts of the figure summaries of the DSMC runs (temperature bands and
curves, the histograms of GRW05 Fig. 4, Crit(t) of RW05 Figs. 3-4, the RW05 moments against the
exact hierarchy), from the numbers the workflow scripts compute.  Pure functions: numbers in,
(text, short) out; the scripts plot and write.
"""

from ..analysis.moment_checks import crit_verdict


def temperature_bands_verdict(inside, t_range):
    """(text, short) of GRW05 Figs. 1-2, RW05 Figs. 1-2: inside maps n to (k, m), the analytic
    curve inside the confidence band at k of the m observation times in t_range."""
    t_min, t_max = t_range
    text = "; ".join(f"n = {n}: analytic curve inside the band at {k}/{m} of the t_m in [{t_min:g}, {t_max:g}]"
                     for n, (k, m) in inside.items())
    short = "analytic curve inside the band at " + ", ".join(f"{k}/{m} (n = {n})" for n, (k, m) in inside.items())
    return text, short


def temperature_curves_verdict(end, t_end):
    """(text, short, gaps) of GRW05 Fig. 3: end lists (n, T(t_end), ci) by increasing n; the
    paper's curves lie from above in n (every gap T_n - T_next > 0) and converge (the gaps shrink)."""
    gaps = [a[1] - b[1] for a, b in zip(end, end[1:])]
    order, shrink = all(g > 0 for g in gaps), all(g1 > g2 for g1, g2 in zip(gaps, gaps[1:]))
    text = (f"T({t_end:g}) = " + ", ".join(f"{T:.4f} ± {ci:.4f} (n = {n})" for n, T, ci in end)
            + ("; decreasing in n (curves from above)" if order else "; not monotone in n at this N")
            + (", gaps between consecutive n shrinking (convergence)" if shrink else ""))
    short = ("curves ordered from above in n" if order else "curves not ordered in n") + (
        ", converging" if shrink else "")
    return text, short, gaps


def histogram_verdict(T0, T, t_end, r_lo, tail_initial, tail_final, r_max):
    """(text, short) of GRW05 Fig. 4: the temperatures, the share of particles beyond r_lo (the
    right panel's lower end) initially and finally, the end of the last non-empty shell."""
    text = (f"T = {T0:.3f} initially, {T:.3f} at t = {t_end:g}; beyond r = {r_lo:g} the final histogram holds "
            f"{tail_final:.3f} of the particles (initial {tail_initial:.2g}), its last non-empty shell ends at "
            f"r = {r_max:g}")
    short = (f"T from {T0:.3g} to {T:.4g}; {tail_final:.3f} of the particles beyond r = {r_lo:g} "
             f"(initially {tail_initial:.2g})")
    return text, short


def crit_curves_verdict(ends, t_end, by_scheme, starts=()):
    """(text, short) of RW05 Figs. 3-4: ends lists (name, Crit(t_end), ci) per run.  By scheme
    (Fig. 4): each scheme's difference to the first (no-splitting) in units of the larger
    half-width.  By n (Fig. 3, ends by increasing n): Crit(0) of each run (starts) and whether
    Crit(t_end) increases with n (from below, as in the paper)."""
    text = f"Crit({t_end:g}) = " + ", ".join(f"{c:.4f} ± {ci:.4f} ({name})" for name, c, ci in ends)
    if by_scheme:
        ref = ends[0]
        diffs = "; ".join(f"{name} {c - ref[1]:+.4f} ({abs(c - ref[1]) / max(ci, ref[2]):.1f} ci)"
                          for name, c, ci in ends[1:])
        short = "Crit(t_end) − no-splitting: " + diffs
        text += "; differences to no-splitting: " + ", ".join(
            f"{name} {c - ref[1]:+.4f} ({abs(c - ref[1]) / max(ci, ref[2]):.1f} ci)" for name, c, ci in ends[1:])
        return text, short
    order = all(a[1] < b[1] for a, b in zip(ends, ends[1:]))
    text += f"; Crit(0) = {', '.join(f'{s:.4f}' for s in starts)}" + (
        "; increasing in n (from below)" if order else "; order in n within the noise")
    short = f"from Crit(0) ≤ {max(starts):.3f} to " + ", ".join(f"{c:.3f}" for _, c, _ in ends) + (
        " (increasing in n)" if order else "")
    return text, short


def rw05_moments_verdict(full, bias):
    """(text, short) of the RW05 moments against the exact hierarchy: full maps n to the rows of
    moment_checks.rw05_moment_rows at every time; the verdict (crit_verdict with the estimator
    bias) is that of the largest n, the others give their largest |sigma|."""
    big = max(full)
    rows = full[big]
    short = crit_verdict(rows, bias)
    end = rows[-1]
    text = (f"{short}; at t = {end['t']:g}: Crit = {end['crit']:.5f} ± {end['crit_ci']:.5f} against exact "
            f"{end['crit_exact']:.5f} (steady 0.11907), <|v−V|^4> = {end['M4']:.3f} ± {end['M4_ci']:.3f} against "
            f"{end['M4_exact']:.3f}; smaller n: " + ", ".join(
                f"n = {n}: max |σ| Crit {max(abs(r['crit_sigma']) for r in rs):.1f}, M4 "
                f"{max(abs(r['M4_sigma']) for r in rs):.1f}" for n, rs in full.items() if n != big))
    return text, short
