"""The report section "Weighted particles" (issue 11, GRW05 Remark 10): the deep tails of Examples
7-9 with SWPM against constant weights, the table of b, a and the depth per example against theory,
and one verdict per example (granboltz.tail_swpm.swpm_verdict)."""

from ..tail_swpm import swpm_verdict
from .numbers import DASH, marked, num, pm

SWPM = "Weighted particles"
INTRO = ("GRW05 Remark 10 suggests a weighted-particle scheme (SWPM) for the tails that constant weights cannot "
         "resolve. Examples 7, 8 and 9 are run again with `dsmc.weights: swpm` (docs/config.md, Weighted "
         "particles; rule file `workflow/rules/grw05_swpm.smk`, config `grw05.tails.swpm`) and compared with the "
         "constant-weight runs of GRW05 §5.3. A shell is *resolved* when the relative confidence half-width of "
         "its density (λ_p = 3.2, over ensembles) is below 30 %; the depth is the smallest f(r)/f(0) of a "
         "resolved shell. b and a come from a weighted fit of ln f = c + χ ln r − a r^b (b, χ free; "
         "`granboltz.local_exponent.tail_fit`) on the pooled shells from f/f(0) < tails.local.tail_from out to "
         "where the resolved profile ends. Goal (issue 11): b within 0.03 of theory with a half-width ≤ 0.03 "
         "and a within 5 % of √(ν_λ/β)/b. The constant-weight runs of the table cost far more CPU time than the "
         "SWPM runs (see Provenance); at *equal* cost (bench/tail_depth.py, 2026-11-30, N = 16) constant weights "
         "with n = 10⁵ resolve 4e−5, 6e−5, 4e−5 (Ex. 7, 8, 9) in 1.5–1.9 CPU s, SWPM with κ = 0.25, N_max = 2000, "
         "n = 1000 resolves 6e−2, 5e−2, 5e−2 in 3.1, 2.5, 1.8 CPU s (κ = 1 and 4 do worse per CPU second).")
WHY = ("**Why SWPM gains little here.** SWPM splits weight at collisions: a collision moves weight "
       "min(g_i, g_j)/(1 + κ) to the post-collision velocities, so it populates with light particles the "
       "velocities that *collisions* produce. In the heated steady state the tail is fed the other way: by the "
       "white-noise diffusion, which carries whole (heavy) particles outwards without splitting them, while "
       "inelastic collisions (α = 1/10) pull fast particles back towards the bulk. The weight in a far shell is "
       "therefore still carried by the rare heavy particles that diffused there, as with constant weights, and "
       "its variance over ensembles is no smaller; the light particles SWPM adds there (hundreds per shell) carry "
       "little of it. Meanwhile every SWPM event costs far more (the reduction dominates, about 80 % of the "
       "time), so at equal CPU time constant weights resolve deeper shells (bench/tail_depth.py, `make bench`). "
       "Reaching f/f(0) ≈ 1e−30 would need a splitting that follows the outward diffusion (importance "
       "splitting on |v|), which is not part of SWPM.")


def swpm_section(items, data, item_blocks):
    """The section "Weighted particles": intro, the table of b, a and the depth of each example from
    the figure summaries, every item registered under that name; returns (blocks, summary rows)."""
    from .render import anchor

    mine = [it for it in items if it["paper"] == SWPM]
    blocks, summary, rows = [("h", 2, SWPM), ("p", INTRO)], [], []
    for it in mine:
        s = (data["summaries"].get(it["summary"]) or {}).get("numbers")
        if not s:
            continue
        ok, _ = swpm_verdict(s)
        rows.append([f"Ex. {s['example']}", num(s["theory_b"]), pm(s["b_swpm"], s["b_swpm_ci"], 3),
                     num(s["a_theory"], 3), pm(s["a_swpm"], s["a_swpm_ci"], 3),
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
        summary.append([SWPM, f"[{it['item']}](#{anchor(SWPM + ' ' + it['item'])})", marked(short), f"`{it['rule']}`"])
    return blocks, summary
