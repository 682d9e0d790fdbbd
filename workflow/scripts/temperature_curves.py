"""GRW05 Fig. 3 (Example 5, §5.2): temperature relaxation for hard spheres.

The ensemble mean of the temperature (uncentred estimator (1/3)|v|^2; N ensembles) against t on
snakemake.params.t_range, one curve per particle number n; the paper's curves lie "from above"
in the order n = 64, 256, 1024, 4096 and converge as n grows. No analytic solution exists for
hard spheres. The summary gives T(t_end) of each n with its confidence half-width and the order
of the curves (granboltz.reproduction.dsmc_verdicts.temperature_curves_verdict).
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import numpy as np  # noqa: E402

from granboltz.reproduction.dsmc import read_dsmc  # noqa: E402
from granboltz.reproduction.dsmc_verdicts import temperature_curves_verdict  # noqa: E402
from granboltz.output.files import write_json  # noqa: E402
from granboltz.output.plotting import figure_summary, pyplot, save_figure  # noqa: E402

plt = pyplot()
runs = sorted((read_dsmc(path) for path in snakemake.input.runs), key=lambda r: r.n)
t_min, t_max = snakemake.params.t_range

fig, ax = plt.subplots(figsize=(4.6, 3.2))
widths = np.linspace(1.6, 0.6, len(runs))
for run, width in zip(runs, widths):
    shown = (run.time >= t_min - 1e-12) & (run.time <= t_max + 1e-12)
    ax.plot(run.time[shown], run.T[shown], "-", color="black", lw=width, label=f"$n = {run.n}$")
    print(f"n={run.n}: T(t_end) = {run.T[-1]:.5f} +- {run.T_ci[-1]:.5f}", file=sys.stderr)
ax.set_xlim(t_min, t_max)
ax.set_xlabel("$t$")
ax.set_ylabel("$T(t)$")
ax.legend(loc="best")
fig.tight_layout()
save_figure(fig, [snakemake.output.png, snakemake.output.pdf])

end = [(run.n, float(run.T[-1]), float(run.T_ci[-1])) for run in runs]
text, short, gaps = temperature_curves_verdict(end, runs[0].time[-1])
write_json(figure_summary(text, short, T_end={str(n): [T, ci] for n, T, ci in end}, gaps=gaps, N=runs[0].N),
              snakemake.output.summary)
