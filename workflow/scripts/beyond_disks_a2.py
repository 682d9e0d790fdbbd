"""Beyond the papers: the Sonine coefficients a2, a3 of hard disks (d = 2, impact normals) in the
homogeneous cooling state (Gaussian thermostat) and the white-noise steady state, against van
Noije-Ernst's d = 2 first Sonine a2 and the second Sonine approximation (a2 and a3; derived,
granboltz.theory.sonine.second_sonine); white-noise T against the energy balance.  Rows, judgement
and verdict: granboltz.reproduction.disks (disk_a2_rows, disk_summary_verdict).  Writes the table, the figure
(a2 above and a3 below, one column per thermostat) and the summary with the computed verdict.
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import numpy as np  # noqa: E402

from granboltz import read_run  # noqa: E402
from granboltz.reproduction.disks import disk_a2_rows, disk_references, disk_summary_verdict  # noqa: E402
from granboltz.output.files import write_csv, write_json  # noqa: E402
from granboltz.output.plotting import figure_summary, label_sonine_panels, pyplot, save_figure  # noqa: E402

rows = disk_a2_rows([read_run(path) for path in snakemake.input.runs], snakemake.params.max_gap)
columns = ["thermostat", "alpha", "n", "N", "a2", "a2_ci", "a3", "a3_ci", "vne_a2", "sonine2_a2", "sonine2_a3", "gap",
           "max_gap", "tol", "diff", "judged", "agrees", "position", "T", "T_ci", "T_theory", "T_maxwellian", "T_tol",
           "T_agrees"]
write_csv(rows, columns, snakemake.output.csv, digits=5)

plt = pyplot()
fig, axes = plt.subplots(2, 2, figsize=(6.3, 4.8), sharex=True, gridspec_kw={"height_ratios": [3, 2], "wspace": 0.35})
alpha_fine = np.linspace(0.15, 1.0, 200)
for column, thermostat in enumerate(("gaussian", "white_noise")):
    top, bottom = axes[:, column]
    refs = np.array([disk_references(thermostat, a, d=2) for a in alpha_fine])
    top.plot(alpha_fine, refs[:, 0], "--", color="black", lw=0.9, label="van Noije–Ernst (first Sonine)")
    top.plot(alpha_fine, refs[:, 1], "-", color="black", lw=0.9, label="second Sonine")
    bottom.plot(alpha_fine, refs[:, 2], "-", color="black", lw=0.9, label="second Sonine")
    mine = [r for r in rows if r["thermostat"] == thermostat]
    for judged, marker, label in ((1, "o", "DSMC, judged"), (0, "s", "DSMC, approximations part")):
        pts = [r for r in mine if r["judged"] == judged]
        if pts:
            top.errorbar([r["alpha"] for r in pts], [r["a2"] for r in pts], yerr=[r["a2_ci"] for r in pts],
                         fmt=marker, ms=3.5, mfc="none", color="black", capsize=1.5, label=label)
            bottom.errorbar([r["alpha"] for r in pts], [r["a3"] for r in pts], yerr=[r["a3_ci"] for r in pts],
                            fmt=marker, ms=3.5, mfc="none", color="black", capsize=1.5)
label_sonine_panels(axes)
legend = {}  # one legend for all panels, below them: the curves fill the panels
for ax in axes[0]:
    legend.update(zip(*reversed(ax.get_legend_handles_labels())))
fig.legend(list(legend.values()), list(legend), loc="upper center", bbox_to_anchor=(0.5, 0.03), ncol=4, fontsize=7)
save_figure(fig, [snakemake.output.png, snakemake.output.pdf])

ok, kind, ours, short = disk_summary_verdict(rows)
write_json(figure_summary(ours, short, kind=kind, ok=ok), snakemake.output.summary)
print(ours, file=sys.stderr)
