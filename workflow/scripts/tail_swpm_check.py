"""The importance check of the weighted-particle tails: one GRW05 example run with the theory
tail as importance function and once with another shape (config grw05.tails.swpm.check).

Left panel: ln f(r)/f(0) of both runs (resolved shells filled).  Right panel: the difference of the
two ln f with its confidence band, which must straddle 0 wherever both are resolved.  Summary: b, a
and the depth of both (granboltz.analysis.tail_swpm.swpm_tail_summary) and the verdict
(granboltz.reproduction.grw05_tails.swpm_check_verdict): the two b agree within
the goal's tolerance on b (0.03) and the two a within its tolerance on a (5 %), i.e. the importance
function does not decide the result.  Whether they also agree within the fits' half-widths is said:
those treat the shells as independent, while the shells of one ensemble share ancestors, so the
difference of two independent runs is the honest measure of the fits' spread.
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import numpy as np  # noqa: E402

from granboltz.output.files import write_json  # noqa: E402
from granboltz.analysis.local_exponent import shells_from_h5  # noqa: E402
from granboltz.output.plotting import figure_summary, pyplot, save_figure  # noqa: E402
from granboltz.analysis.tail_swpm import shell_profile, swpm_tail_summary  # noqa: E402
from granboltz.reproduction.grw05_tails import importance_label, swpm_check_verdict  # noqa: E402

plt = pyplot()
tails, example = snakemake.params.tails, snakemake.params.example
swpm_cfg, local = tails["swpm"], tails["local"]
runs = {"theory": shells_from_h5(snakemake.input.theory[0], steady=True),
        "check": shells_from_h5(snakemake.input.check[0], steady=True)}
splits = {"theory": snakemake.params.theory_split, "check": snakemake.params.check_split}
s = {k: swpm_tail_summary(v, example, local, swpm_cfg["max_rel_ci"])[0] for k, v in runs.items()}


fig, (ax, bx) = plt.subplots(1, 2, figsize=(8.4, 3.4))
prof = {k: shell_profile(v) for k, v in runs.items()}
for k, colour in (("theory", "black"), ("check", "tab:red")):
    r, ratio, rel = prof[k]
    ok = np.isfinite(ratio) & (ratio > 0)
    good = ok & (rel < swpm_cfg["max_rel_ci"])
    ax.plot(r[good], np.log(ratio[good]), "o", ms=2.2, color=colour, label=f"{importance_label(splits[k])}, resolved")
    ax.plot(r[ok & ~good], np.log(ratio[ok & ~good]), "o", ms=2.2, mfc="none", color=colour, label="unresolved")
ax.set_xlabel("$r = |v|$")
ax.set_ylabel("$\\ln f(r)/f(0)$")
ax.legend(loc="lower left", fontsize=6.5)
r, (_, f1, e1), (_, f2, e2) = prof["theory"][0], prof["theory"], prof["check"]
both = np.isfinite(f1) & np.isfinite(f2) & (f1 > 0) & (f2 > 0) & (e1 < 1) & (e2 < 1)
d, hw = np.log(f2[both] / f1[both]), np.hypot(e1[both], e2[both])  # relative half-widths ~ of ln f
bx.fill_between(r[both], d - hw, d + hw, color="0.7", lw=0)
bx.plot(r[both], d, "-", color="black", lw=1)
bx.axhline(0.0, color="black", lw=0.7, ls="-.")
bx.set_xlabel("$r = |v|$")
bx.set_ylabel("$\\ln f_{check} - \\ln f_{theory}$")
fig.suptitle(f"GRW05 Example {example}, weighted particles: the importance function does not change the tail",
             fontsize=8)
fig.tight_layout()
save_figure(fig, [snakemake.output.png, snakemake.output.pdf])

ok, kind, text, short = swpm_check_verdict(s["theory"], s["check"], splits["theory"], splits["check"])
print(text, file=sys.stderr)
write_json(figure_summary(text, short, kind=kind, reached=ok, theory=s["theory"], check=s["check"]),
           snakemake.output.summary)
