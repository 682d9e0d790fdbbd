"""Beyond the papers: the tail of the homogeneous cooling state.  The local exponent
b(r) = 1 + d ln(-d_r ln f)/d ln r (granboltz.analysis.local_exponent, as for the tails of GRW05) of the
scaled velocity distribution of hard spheres under the Gaussian thermostat, averaged over the
steady observations, against the predicted exponential tail f ~ e^{-A c} (b = 1 for hard spheres
in the HCS; van Noije & Ernst 1998).  b(r) leaves the Gaussian core (b = 2) and falls towards 1.
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import numpy as np  # noqa: E402

from granboltz import read_run  # noqa: E402
from granboltz.reproduction.beyond import steady_histogram, tail_item_verdict  # noqa: E402
from granboltz.output.files import write_csv, write_json  # noqa: E402
from granboltz.analysis.local_exponent import local_exponent, pool_shells  # noqa: E402
from granboltz.output.plotting import figure_summary, pyplot, save_figure  # noqa: E402

p = snakemake.params
run = read_run(snakemake.input.run)
alpha = float(run.config["dsmc"]["alpha"])
pooled = pool_shells(steady_histogram(run, p.steady_from), min_count=p.min_count)
res = local_exponent(pooled, half_width=p.half_width)
rows = [{"alpha": alpha, "r": r, "b": b, "ci_b": c, "at_bound": int(ab), "max_ci": p.max_ci}
        for r, b, c, ab in zip(res["r"], res["b"], res["ci_b"], res["at_bound"])]
write_csv(rows, ["alpha", "r", "b", "ci_b", "at_bound", "max_ci"], snakemake.output.csv, digits=5)

plt = pyplot()
fig, ax = plt.subplots(figsize=(4.2, 2.8))
ok = (res["ci_b"] <= 1.0) & ~res["at_bound"]
ax.fill_between(res["r"][ok], (res["b"] - res["ci_b"])[ok], (res["b"] + res["ci_b"])[ok], color="0.85", lw=0)
ax.plot(res["r"][ok], res["b"][ok], "-", color="black", label=f"ours, hard spheres, $\\alpha$ = {alpha:g}")
ax.axhline(2.0, color="black", lw=0.5, ls=":", label="Maxwellian core, b = 2")
ax.axhline(1.0, color="black", lw=0.8, ls="--", label="HCS tail, b = 1")
ax.set_xlabel("$|v|$ ($T = T_0$ = %g)" % run.config["dsmc"]["initial"]["temperature"])
ax.set_ylabel("local exponent $b(r)$")
ax.set_ylim(0, 3)
ax.legend()
save_figure(fig, [snakemake.output.png, snakemake.output.pdf])

good, kind, text, short, far = tail_item_verdict(res, p.max_ci)
write_json(figure_summary(text, short, kind=kind, ok=good, far=far), snakemake.output.summary)
print(text, np.round(res["b"], 2), file=sys.stderr)
