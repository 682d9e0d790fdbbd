"""GRW05 Figs. 1, 2 (Examples 3, 4, §5.2) and RW05 Figs. 1, 2 (§4.1): temperature relaxation.

One panel per particle number n (side by side for two, 2 x 2 for up to four): the confidence
band [mean - ci, mean + ci] of the temperature (GRW05 eq. 31, lambda_p = 3.2; two solid lines)
against the analytic solution (GRW05 eq. 16 = eqs. 34, 36; RW05 eq. 28; dashed) on the time
interval snakemake.params.t_range. The temperature is the uncentred estimator (1/3)|v|^2, the
one behind the papers' tables (RW05 §4.1). The summary counts the t_m at which the analytic
curve lies inside the band (granboltz.reproduction.dsmc_verdicts.temperature_bands_verdict).
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import numpy as np  # noqa: E402

from granboltz.reproduction.dsmc import read_dsmc  # noqa: E402
from granboltz.reproduction.dsmc_verdicts import temperature_bands_verdict  # noqa: E402
from granboltz.output.files import write_json  # noqa: E402
from granboltz.output.plotting import figure_summary, pyplot, save_figure  # noqa: E402
from granboltz.theory.dimension import dsmc_geometry  # noqa: E402
from granboltz.theory import analytic_temperature, run_analytic_temperature  # noqa: E402

plt = pyplot()
runs = sorted((read_dsmc(path) for path in snakemake.input.runs), key=lambda r: r.n)
t_min, t_max = snakemake.params.t_range

ncols = 2 if len(runs) > 1 else 1
nrows = (len(runs) + ncols - 1) // ncols
fig, axes = plt.subplots(nrows, ncols, figsize=(6.3, 2.2 * nrows + 0.3), squeeze=False)
t_fine = np.linspace(t_min, t_max, 400)
inside = {}
for ax, run in zip(axes.flat, runs):
    shown = (run.time >= t_min - 1e-12) & (run.time <= t_max + 1e-12)
    t, mean, ci = run.time[shown], run.T[shown], run.T_ci[shown]
    exact_t = run_analytic_temperature(run)[shown]
    inside[run.n] = (int(np.sum(np.abs(mean - exact_t) <= ci)), int(t.size))
    d = run.dsmc
    exact = analytic_temperature(t_fine, d["initial"]["temperature"], d["alpha"], d["beta"], d["gamma"],
                                    d["kernel"]["C"], *dsmc_geometry(d))
    ax.plot(t, mean + ci, "-", color="black", label="confidence interval (31)")
    ax.plot(t, mean - ci, "-", color="black")
    ax.plot(t_fine, exact, color="black", dashes=(4, 2.5), label="analytic solution")
    ax.set_xlim(t_min, t_max)
    ax.text(0.05, 0.92, f"$n = {run.n}$", transform=ax.transAxes, va="top")
    ax.set_ylabel("$T(t)$")
    ax.set_xlabel("$t$")
    print(f"n={run.n}: analytic inside the band at {inside[run.n][0]}/{inside[run.n][1]} t_m", file=sys.stderr)
for ax in axes.flat[len(runs):]:
    ax.set_visible(False)
axes.flat[0].legend(loc="lower right")
fig.tight_layout()
save_figure(fig, [snakemake.output.png, snakemake.output.pdf])

text, short = temperature_bands_verdict(inside, (t_min, t_max))
write_json(figure_summary(text, short, inside={str(n): v for n, v in inside.items()}, N=runs[0].N),
              snakemake.output.summary)
