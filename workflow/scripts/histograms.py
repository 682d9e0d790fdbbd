"""GRW05 Fig. 4 (Example 7, §5.3): initial and final histograms of the radial velocity.

f_k (GRW05 eq. 37: fraction of particles in the shell r_{k-1} <= |v| < r_k, r_k = k R/K,
averaged over the N ensembles) against r_k: the initial Maxwellian (thick) and the final,
steady distribution (thin). Left r in params.left (paper [0, 10]); right the tail, r in
params.right (paper [2, 10]), zoomed on the final histogram. The summary gives the temperatures
and the share of particles beyond the right panel's lower end
(granboltz.reproduction.dsmc_verdicts.histogram_verdict).
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from granboltz.reproduction.dsmc import read_histogram  # noqa: E402
from granboltz.reproduction.dsmc_verdicts import histogram_verdict  # noqa: E402
from granboltz.output.files import write_json  # noqa: E402
from granboltz.output.plotting import figure_summary, pyplot, save_figure  # noqa: E402

plt = pyplot()
(path,) = snakemake.input.runs
hist = read_histogram(path)
r = hist["edges"][1:]  # r_k = k h, k = 1..K (paper's 1-based shells)
first, last = hist["mean"][0, :-1], hist["mean"][-1, :-1]
T0, T = float(hist["T"][0]), float(hist["T"][-1])

fig, (left, right) = plt.subplots(1, 2, figsize=(6.3, 2.6))
for ax, (lo, hi) in ((left, snakemake.params.left), (right, snakemake.params.right)):
    shown = (r >= lo - 1e-12) & (r <= hi + 1e-12)
    ax.plot(r[shown], first[shown], "-", color="black", lw=1.8, label="initial")
    ax.plot(r[shown], last[shown], "-", color="black", lw=0.7, label="final")
    ax.set_xlim(lo, hi)
    ax.set_xlabel("$r$")
zoom = (r >= snakemake.params.right[0]) & (r <= snakemake.params.right[1])
right.set_ylim(0, 1.15 * last[zoom].max())
left.set_ylabel("$f_k$")
left.legend(loc="upper right")
fig.tight_layout()
save_figure(fig, [snakemake.output.png, snakemake.output.pdf])

lo = snakemake.params.right[0]
tail_first, tail_last = float(first[r > lo].sum()), float(last[r > lo].sum())
r_max = float(r[hist["counts"][-1, :-1] > 0].max())
text, short = histogram_verdict(T0, T, hist["time"][-1], lo, tail_first, tail_last, r_max)
print(text, file=sys.stderr)
write_json(figure_summary(text, short, T_initial=T0, T_final=T, tail_final=tail_last, tail_initial=tail_first,
                                r_max=r_max, n=hist["n"], N=hist["N"]), snakemake.output.summary)
