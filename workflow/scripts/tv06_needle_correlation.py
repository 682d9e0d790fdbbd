"""TV06 Fig. 7 and the temperatures of §3.2: the needle (uniform rod, Gaussian bath).

Fig. 7: the correlation coefficient R = <v^2 w^2>/(<v^2><w^2>) (eq. 30) against alpha for each
M, with 99.9 % confidence intervals over the N ensembles; R = 1 at alpha = 1 (equipartition),
the exact check. The table (granboltz.reproduction.tv06_tables.needle_rows) adds T_trans/T_B and T_rot/T_B and checks
the statement of §3.2, T_B > T_translational > T_rotational for alpha < 1, point by point; the
summary: granboltz.reproduction.tv06_verdicts.needle_correlation_verdict.
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)


from granboltz.output.files import write_csv, write_json  # noqa: E402
from granboltz.output.plotting import figure_summary, pyplot, save_figure  # noqa: E402
from granboltz.reproduction.tv06_tables import NEEDLE_COLUMNS, needle_rows, read_tv06  # noqa: E402
from granboltz.reproduction.tv06_verdicts import needle_correlation_verdict  # noqa: E402

plt = pyplot()
runs = [read_tv06(path) for path in snakemake.input.runs]
if any(r["model"] != "needle" for r in runs):
    raise ValueError("Fig. 7 needs needle runs")
rows = needle_rows(runs)
write_csv(rows, NEEDLE_COLUMNS, snakemake.output.csv, digits=6)

fig, ax = plt.subplots(figsize=(4.4, 3.3))
masses = sorted({r["M"] for r in rows})
for k, M in enumerate(masses):
    mine = [r for r in rows if r["M"] == M]
    ax.errorbar([r["alpha"] + 0.006 * (k - 1) for r in mine], [r["R"] for r in mine], yerr=[r["R_ci"] for r in mine],
                fmt="o-s-^-v-"[2 * (k % 4):2 * (k % 4) + 2], ms=4, mfc="white", mec="black", color="black", lw=0.7,
                elinewidth=0.7, capsize=2, label=f"$M = {M:g}$")
ax.axhline(1.0, color="0.5", lw=0.6, dashes=(2, 2))
ax.set_xlim(-0.03, 1.03)
ax.set_xlabel(r"$\alpha$")
ax.set_ylabel(r"$R = \langle v^2\omega^2\rangle / \langle v^2\rangle\langle\omega^2\rangle$")
ax.legend(loc="upper right")
fig.tight_layout()
save_figure(fig, [snakemake.output.png, snakemake.output.pdf])

_, ours, short, numbers = needle_correlation_verdict(rows, snakemake.output.csv)
print(ours, file=sys.stderr)
write_json(figure_summary(ours, short, **numbers), snakemake.output.summary)
