"""RW05 Fig. 3 (§4.1) against the exact moment hierarchy (lambda = 0).

For each run of Fig. 3 (n, N): <|v - V|^4>(t) (/moment_4) relative to the exact M_4(t) and
Crit(t) (crit_of_means) minus the exact Crit(t) (granboltz.theory.maxwell_hierarchy), with their bands
(lambda_p = 3.2).  Output csv: every n at the times params.times (moment_checks.RW05_COLUMNS).
Summary: the verdict for the largest n (is the exact Crit inside its band at every observation
time?), with the estimator bias of Crit at the ensemble means (moment_checks.crit_estimator_bias);
granboltz.reproduction.dsmc_verdicts.rw05_moments_verdict.
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import numpy as np  # noqa: E402

from granboltz.reproduction.dsmc import read_dsmc  # noqa: E402
from granboltz.output.files import write_csv, write_json  # noqa: E402
from granboltz.analysis.moment_checks import RW05_COLUMNS, crit_estimator_bias, rw05_moment_rows  # noqa: E402
from granboltz.reproduction.dsmc_verdicts import rw05_moments_verdict  # noqa: E402
from granboltz.output.plotting import figure_summary, pyplot, save_figure  # noqa: E402

plt = pyplot()
runs = sorted((read_dsmc(path) for path in snakemake.input.runs), key=lambda r: r.n)
fig, (ax_m, ax_c) = plt.subplots(1, 2, figsize=(7.6, 3.2))
table, full = [], {}
for run, shade in zip(runs, ["0.8", "0.6", "0.35", "0.15"]):
    rows = rw05_moment_rows(run)
    full[run.n] = rows
    table += rw05_moment_rows(run, snakemake.params.times)
    t = np.array([r["t"] for r in rows])
    for ax, key, scale in ((ax_m, "M4", "M4_exact"), (ax_c, "crit", None)):
        dev = np.array([r[key] - r[key + "_exact"] for r in rows])
        ci = np.array([r[key + "_ci"] for r in rows])
        div = np.array([r[scale] for r in rows]) if scale else 1.0
        ax.fill_between(t, (dev - ci) / div, (dev + ci) / div, color=shade, alpha=0.5, lw=0)
        ax.plot(t, dev / div, color=shade, lw=0.9, label=f"$n = {run.n}$, $N = {run.N}$")
for ax, label in ((ax_m, r"$\langle|v - V|^4\rangle / M_4^{\rm exact} - 1$"),
                  (ax_c, r"Crit$(t) - $Crit$^{\rm exact}(t)$")):
    ax.axhline(0.0, color="black", lw=0.7)
    ax.set_xlim(t[0], t[-1])
    ax.set_xlabel("$t$")
    ax.set_ylabel(label)
ax_c.legend(loc="lower right", fontsize=7)
fig.tight_layout()
save_figure(fig, [snakemake.output.png, snakemake.output.pdf])
write_csv(table, RW05_COLUMNS, snakemake.output.csv, digits=6)

bias = float(np.max(crit_estimator_bias(runs[-1])))
text, short = rw05_moments_verdict(full, bias)
print(text, file=sys.stderr)
write_json(figure_summary(text, short, crit_bias=bias), snakemake.output.summary)
