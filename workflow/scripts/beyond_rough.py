"""Beyond the papers: theta = T_rot/T_tr of rough hard spheres (kappa = 2/5) in the homogeneous
cooling state (Gaussian thermostat) and under white noise on the translational velocities,
against the Maxwellian approximation of Huthmann-Zippelius and Luding et al. (granboltz.reproduction.rough).
Rows, interval and verdict: granboltz.reproduction.rough (rough_rows, rough_verdict).  Writes the table, the
figure (theta against beta, one panel per thermostat, a curve per alpha) and the summary with the
computed verdict: a comparison with an approximation, never a failure.
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import numpy as np  # noqa: E402

from granboltz import read_run  # noqa: E402
from granboltz.output.files import write_csv, write_json  # noqa: E402
from granboltz.output.plotting import figure_summary, pyplot, save_figure  # noqa: E402
from granboltz.reproduction.rough import rough_rows, rough_verdict, theta  # noqa: E402

rows = rough_rows([read_run(path) for path in snakemake.input.runs])
columns = ["thermostat", "alpha", "beta", "theta", "theta_ci", "theta_maxwellian", "difference", "kappa", "n", "N",
           "T_tr", "T_rot"]
write_csv(rows, columns, snakemake.output.csv, digits=5)

plt = pyplot()
fig, axes = plt.subplots(1, 2, figsize=(6.3, 3.2), sharey=True)
beta_fine = np.linspace(-0.2, 1.0, 121)
titles = {"gaussian": "Gaussian thermostat (HCS)", "white_noise": "white noise (translational)"}
styles = ["-", "--", ":", "-."]
markers = "osd^v"
for ax, thermostat in zip(axes, ("gaussian", "white_noise")):
    mine = [r for r in rows if r["thermostat"] == thermostat]
    for k, alpha in enumerate(sorted({r["alpha"] for r in mine}, reverse=True)):
        pts = [r for r in mine if r["alpha"] == alpha]
        ref = theta(thermostat, alpha, beta_fine, snakemake.params.kappa, d=3)
        ax.plot(beta_fine, ref, styles[k % 4], color="black", lw=0.9,
                label=f"Maxwellian, α = {alpha:g}" if thermostat == "gaussian" else
                ("Maxwellian (any α)" if k == 0 else None))
        ax.errorbar([r["beta"] for r in pts], [r["theta"] for r in pts], yerr=[r["theta_ci"] for r in pts],
                    fmt=markers[k % 5], ms=3.5, mfc="none", color="black", capsize=1.5, label=f"DSMC, α = {alpha:g}")
    ax.set_title(titles[thermostat])
    ax.set_xlabel("$\\beta$")
    ax.legend(fontsize=6)
axes[0].set_ylabel("$\\theta = T_\\mathrm{rot}/T_\\mathrm{tr}$")
save_figure(fig, [snakemake.output.png, snakemake.output.pdf])

ours, short = rough_verdict(rows)
write_json(figure_summary(ours, short, max_difference=max((abs(r["difference"]) for r in rows), default=None)),
           snakemake.output.summary)
print(ours, file=sys.stderr)
