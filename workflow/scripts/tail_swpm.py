"""GRW05 Examples 7-9 with weighted particles (SWPM): ln f against r for both methods, b(r).

Left panel: ln(f/f(0)) per shell with its confidence band (z = 3.2), SWPM and constant weights;
filled markers are resolved shells (relative half-width below tails.swpm.max_rel_ci), open ones
are not: the constant-weight noise floor is where its open markers begin.  Dashed: the theory
tail's slope a r^b (a, b to leading order) through the SWPM fit's intercept.  Right panel: the
local exponent b(r) of both runs (granboltz.analysis.local_exponent) against theory.  Summary: the numbers
of granboltz.analysis.tail_swpm.SWPM_KEYS and the verdict
(granboltz.reproduction.grw05_tails.tail_swpm_item_verdict).
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import numpy as np  # noqa: E402

from granboltz.output.files import write_json  # noqa: E402
from granboltz.analysis.local_exponent import local_exponent, pool_shells, shells_from_h5  # noqa: E402
from granboltz.output.plotting import figure_summary, pyplot, save_figure  # noqa: E402
from granboltz.analysis.tail_swpm import effective_counts, shell_profile, swpm_tail_summary  # noqa: E402
from granboltz.reproduction.grw05_tails import tail_swpm_item_verdict  # noqa: E402

plt = pyplot()
tails, example = snakemake.params.tails, snakemake.params.example
swpm_cfg, local = tails["swpm"], tails["local"]
(swpm_path,) = snakemake.input.swpm
(constant_path,) = snakemake.input.constant
swpm, constant = shells_from_h5(swpm_path, steady=True), shells_from_h5(constant_path)
s, curve = swpm_tail_summary(swpm, example, local, swpm_cfg["max_rel_ci"], constant)

fig, (ax, bx) = plt.subplots(1, 2, figsize=(8.4, 3.4))
for shells, colour, name in ((constant, "0.55", "constant weights"), (swpm, "black", "SWPM")):
    r, ratio, rel = shell_profile(shells)
    ok = np.isfinite(ratio) & (ratio > 0)
    good = ok & (rel < swpm_cfg["max_rel_ci"])
    band = ok & (rel < 1)
    ax.fill_between(r[band], np.log(ratio[band] * (1 - rel[band])), np.log(ratio[band] * (1 + rel[band])),
                    color=colour, alpha=0.2, lw=0)
    ax.plot(r[good], np.log(ratio[good]), "o", ms=2.5, color=colour, label=f"{name}, resolved")
    ax.plot(r[ok & ~good], np.log(ratio[ok & ~good]), "o", ms=2.5, mfc="none", color=colour,
            label=f"{name}, unresolved")
rs = np.linspace(s["fit_r_lo"], max(s["fit_r_hi"], s["fit_r_lo"] + 1), 100)
ax.plot(rs, -s["a_theory"] * rs ** s["theory_b"] + (s["a_theory"] * s["fit_r_lo"] ** s["theory_b"]
        + np.log(max(np.interp(s["fit_r_lo"], *shell_profile(swpm)[:2]), 1e-300))), "--", color="0.3", lw=0.9,
        label=f"theory slope $a r^b$, $b = {s['theory_b']:g}$")
ax.axhline(np.log(s["depth_swpm"]) if s["depth_swpm"] > 0 else np.nan, color="black", ls=":", lw=0.8)
ax.axhline(np.log(s["depth_constant"]) if s["depth_constant"] > 0 else np.nan, color="0.55", ls=":", lw=0.8)
ax.set_xlabel("$r = |v|$")
ax.set_ylabel("$\\ln f(r)/f(0)$")
ax.legend(loc="lower left", fontsize=6.5)

for shells, colour, name, c in ((constant, "0.55", "constant weights", None), (swpm, "black", "SWPM", curve)):
    if c is None:
        c = local_exponent(pool_shells(effective_counts(shells), local["pool_min_count"]), half_width=local["half_width"],
                           step=local["step"])
    if not len(c.get("r", [])):
        continue
    ok = ~c["at_bound"] & (c["ci_b"] < 1.0)
    bx.fill_between(c["r"][ok], c["b"][ok] - c["ci_b"][ok], c["b"][ok] + c["ci_b"][ok], color=colour, alpha=0.2, lw=0)
    bx.plot(c["r"][ok], c["b"][ok], "-", color=colour, lw=1.1, label=f"$b(r)$, {name}")
bx.axhline(s["theory_b"], color="black", lw=0.7, ls="-.", label=f"theory $b = {s['theory_b']:g}$")
bx.set_ylim(0.0, 3.0)
bx.set_xlabel("$r = |v|$")
bx.set_ylabel("$b(r)$")
bx.legend(loc="upper right", fontsize=6.5)
fig.suptitle(f"GRW05 Example {example}: weighted particles (SWPM, κ = {swpm_cfg['kappa']:g}) and constant weights",
             fontsize=8)
fig.tight_layout()
save_figure(fig, [snakemake.output.png, snakemake.output.pdf])

ok, kind, text, short = tail_swpm_item_verdict(s, example)
print(text, file=sys.stderr)
write_json(figure_summary(text, short, kind=kind, reached=ok, **s,
                          curve={k: curve[k].tolist() for k in ("r", "b", "ci_b")} if len(curve) else {}),
           snakemake.output.summary)
