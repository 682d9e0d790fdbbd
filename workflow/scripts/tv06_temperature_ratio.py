"""TV06 Fig. 3 (§3.1): T/T_B of the Gillespie intruder in a Gaussian bath against alpha, with the
exact curve of Martin and Piasecki, eq. (18), T/T_B = (1 + alpha)/(2 + (1 - alpha)/M).

Symbols: the mean over the N ensembles with its 99.9 % confidence interval (the simulator's
ci = 3.2 sqrt(var/N)); solid curve: eq. (18). The table (granboltz.reproduction.tv06_tables.temperature_rows) has every
point with the exact value, z = (mean - exact)/(ci/3.2) and whether the exact value is within
the ci; the summary counts those (granboltz.reproduction.tv06_verdicts.temperature_ratio_verdict).
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import numpy as np  # noqa: E402

from granboltz.output.files import write_csv, write_json  # noqa: E402
from granboltz.output.plotting import figure_summary, pyplot, save_figure  # noqa: E402
from granboltz.theory import gaussian_temperature_ratio  # noqa: E402
from granboltz.reproduction.tv06_verdicts import temperature_ratio_verdict  # noqa: E402
from granboltz.reproduction.tv06_tables import read_tv06, TEMPERATURE_COLUMNS, temperature_rows  # noqa: E402

plt = pyplot()
runs = [read_tv06(path) for path in snakemake.input.runs]
if any(r["model"] != "intruder" or r["bath"] != "gaussian" for r in runs):
    raise ValueError("Fig. 3 needs intruder runs in the Gaussian bath")
rows = temperature_rows(runs)
write_csv(rows, TEMPERATURE_COLUMNS, snakemake.output.csv, digits=6)

fig, ax = plt.subplots(figsize=(4.2, 3.2))
alpha = np.linspace(0.0, 1.0, 201)
for k, M in enumerate(sorted({r["M"] for r in rows}, reverse=True)):
    mine = [r for r in rows if r["M"] == M]
    ax.plot(alpha, gaussian_temperature_ratio(alpha, M), color="black", lw=0.9,
            label="eq. (18)" if k == 0 else None)
    ax.errorbar([r["alpha"] for r in mine], [r["T_ratio"] for r in mine], yerr=[r["ci"] for r in mine],
                fmt="os^v"[k % 4], ms=4, mfc="white", mec="black", ecolor="black", elinewidth=0.8, capsize=2,
                label=f"Gillespie, $M = {M:g}$")
ax.set_xlim(-0.02, 1.02)
ax.set_xlabel(r"$\alpha$")
ax.set_ylabel(r"$T/T_B$")
ax.legend(loc="upper left")
fig.tight_layout()
save_figure(fig, [snakemake.output.png, snakemake.output.pdf])

_, ours, short, numbers = temperature_ratio_verdict(rows, snakemake.output.csv)
print(ours, file=sys.stderr)
write_json(figure_summary(ours, short, **numbers), snakemake.output.summary)
