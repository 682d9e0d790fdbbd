"""Beyond the papers: T1/T2 of the homogeneous cooling state (Gaussian thermostat) of a binary
mixture of hard spheres, equal diameters, x1 = 1/2, against the Maxwellian approximation of
Garzó-Dufty (granboltz.reproduction.mixtures).  Rows, interval and verdict: granboltz.reproduction.mixtures (mixture_rows,
mixture_verdict).  Writes the table, the figure (T1/T2 against alpha, one curve per mass ratio,
and the relative difference below) and the summary with the computed verdict: a comparison with
an approximation, never a failure.
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import numpy as np  # noqa: E402

from granboltz import read_run  # noqa: E402
from granboltz.output.files import write_csv, write_json  # noqa: E402
from granboltz.reproduction.mixtures import mixture_rows, mixture_verdict, temperature_ratio  # noqa: E402
from granboltz.output.plotting import figure_summary, pyplot, save_figure  # noqa: E402

rows = mixture_rows([read_run(path) for path in snakemake.input.runs])
columns = ["mass_ratio", "alpha", "t1_t2", "t1_t2_ci", "t1_t2_garzo_dufty", "difference", "x1", "n", "N", "T1", "T1_ci",
           "T2", "T2_ci", "correlation"]
write_csv(rows, columns, snakemake.output.csv, digits=5)

plt = pyplot()
fig, (top, bottom) = plt.subplots(2, 1, figsize=(4.8, 4.8), sharex=True, gridspec_kw={"height_ratios": [3, 2]})
alpha_fine = np.linspace(0.4, 1.0, 121)
markers = "osd^v"
for k, m in enumerate(sorted({r["mass_ratio"] for r in rows})):
    mine = [r for r in rows if r["mass_ratio"] == m]
    gd = [temperature_ratio("gaussian", m, a, snakemake.params.x1, d=3) for a in alpha_fine]
    top.plot(alpha_fine, gd, "-", color="black", lw=0.9, label="Garzó–Dufty" if k == 0 else None)
    top.errorbar([r["alpha"] for r in mine], [r["t1_t2"] for r in mine], yerr=[r["t1_t2_ci"] for r in mine],
                 fmt=markers[k % 5], ms=3.5, mfc="none", color="black", capsize=1.5, label=f"DSMC, $m_1/m_2$ = {m:g}")
    bottom.errorbar([r["alpha"] for r in mine], [100 * r["difference"] for r in mine],
                    yerr=[100 * r["t1_t2_ci"] / r["t1_t2_garzo_dufty"] for r in mine], fmt=markers[k % 5], ms=3.5,
                    mfc="none", color="black", capsize=1.5)
bottom.axhline(0.0, color="grey", lw=0.4)
top.set_ylabel("$T_1/T_2$")
bottom.set_ylabel("DSMC/GD − 1 (%)")
bottom.set_xlabel("$\\alpha$")
top.legend(fontsize=7)
save_figure(fig, [snakemake.output.png, snakemake.output.pdf])

ours, short = mixture_verdict(rows)
write_json(figure_summary(ours, short, max_difference=max((abs(r["difference"]) for r in rows), default=None)),
           snakemake.output.summary)
print(ours, file=sys.stderr)
