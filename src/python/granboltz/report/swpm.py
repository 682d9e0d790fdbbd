"""The report section "Weighted particles" (GRW05 Remark 10): the deep tails of Examples
7-9 with SWPM against constant weights, the table of b, a and the depth per example against theory,
and one verdict per example (granboltz.tail_swpm.swpm_verdict)."""

from ..analysis.tail_swpm import swpm_verdict
from .numbers import DASH, num, pm

SWPM = "Weighted particles"
INTRO = ("GRW05 Remark 10 suggests a weighted-particle scheme (SWPM) for the tails that constant weights cannot "
         "resolve. Examples 7, 8 and 9 are run again with `dsmc.weights: swpm` and importance splitting along the "
         "diffusion path (`dsmc.weights.split`; docs/config.md, Weighted particles; rule file "
         "`workflow/rules/grw05_swpm.smk`, config `grw05.tails.swpm`): every split interval all particles are kicked "
         "to the current time, a tail particle heavier than its target weight w*(r) ∝ r² exp(−a r^b) is split into "
         "equal copies and light ones play roulette in pairs, so that every shell of the tail keeps about as many "
         "particles however deep it is. The importance function uses the theory's a and b; it sets the variance, "
         "not the mean (splitting and roulette are unbiased; a test recovers the exact Maxwell moments M_2 … M_10 "
         "with a deliberately wrong importance). Each run lasts twice the example's t_end and each ensemble's "
         "histogram is averaged over the steady window (t_end, 2 t_end]; the confidence intervals come from the "
         "ensembles. A shell is *resolved* when the relative confidence half-width of its density (λ_p = 3.2) is "
         "below 30 %; the depth is the smallest f(r)/f(0) of the resolved profile, counted from the core outwards. "
         "b and a come from a weighted fit of ln f = c + χ ln r − a r^b (b, χ free; "
         "`granboltz.local_exponent.tail_fit`) on the pooled shells from f/f(0) < tails.local.tail_from out to "
         "where the resolved profile ends. Its half-widths treat the shells as independent, but the particles of one "
         "ensemble's shells share ancestors, so they understate the spread; the importance check below (two "
         "independent runs of Example 7) shows by how much. Goal: b within 0.03 of theory with a half-width ≤ 0.03 "
         "and a within 5 % of √(ν_λ/β)/b. The constant-weight column is the final state of the n = 10⁷ runs of "
         "GRW05 §5.3 (see Provenance for both costs).")
WHY = ("**Why splitting, and why along the path.** SWPM by itself splits weight only at collisions: a collision "
       "moves weight min(g_i, g_j)/(1 + κ) to the post-collision velocities, so it populates the velocities that "
       "*collisions* produce. In the heated steady state the tail is fed the other way, by the white-noise "
       "diffusion, which carries whole particles outwards, while inelastic collisions (α = 1/10) pull fast "
       "particles back towards the bulk. Plain SWPM (κ = 1/4, n = 16 000, N = 100, the previous publication) "
       "therefore resolved only 9e−8, 1.6e−6 and 5.8e−7, no deeper than constant weights, and the fit of b did "
       "not converge. Splitting at sweeps whose kicks move a particle by half an e-fold of w* follows the "
       "diffusion outwards. Two details matter: w* grows as r² (so a deep shell is not crowded), and when the tail "
       "holds more than N_max/2 particles its targets are raised so that roulette thins it; otherwise the "
       "reduction merges the bulk into a few heavy particles and biases every moment (measured: M_10 −34 %).")


def _fixed(x, ci, decimals=3):
    """'x ± ci' with both to `decimals` decimals (b and a are compared at 0.03 and 5 %); '–' (a
    missing number, so that the column stays numeric) if x is missing, pm() if only ci is."""
    if x == x and ci == ci:
        return f"{x:.{decimals}f} ± {ci:.{decimals}f}"
    return DASH if x != x else pm(x, ci, 3)


def swpm_section(items, data, item_blocks):
    """The section "Weighted particles": intro, the table of b, a and the depth of each example from
    the figure summaries, every item registered under that name; returns (blocks, summary rows)."""
    from .summary import summary_rows

    mine = [it for it in items if it["paper"] == SWPM]
    blocks, parts, rows = [("h", 2, SWPM), ("p", INTRO)], [], []
    for it in mine:
        s = (data["summaries"].get(it["summary"]) or {}).get("numbers")
        if not s:
            continue
        name = f"Ex. {s.get('example', '')}"
        if "check" in s:  # the importance check: its run with the other importance function
            s = s["check"]
            name = f"Ex. {s['example']}, importance check"
        ok, _ = swpm_verdict(s)
        rows.append([name, num(s["theory_b"]), _fixed(s["b_swpm"], s["b_swpm_ci"]),
                     num(s["a_theory"], 3), _fixed(s["a_swpm"], s["a_swpm_ci"]),
                     f"{100 * (s['a_swpm'] / s['a_theory'] - 1):+.0f} %" if s["a_swpm"] == s["a_swpm"] else DASH,
                     f"{s['depth_swpm']:.1e}",
                     f"{s['depth_constant']:.1e}" if s["depth_constant"] == s["depth_constant"] else DASH,
                     "reached" if ok else "not reached"])
    if rows:
        blocks.append(("table", ["example", "b theory", "b SWPM ± CI", "a theory", "a SWPM ± CI", "a vs theory",
                                 "depth SWPM f/f(0)", "depth constant f/f(0)", "goal"], rows))
    blocks.append(("p", WHY))
    for it in mine:
        item, short = item_blocks(it, data)
        blocks += item
        parts.append((it, short))
    return blocks, summary_rows(SWPM, parts)
