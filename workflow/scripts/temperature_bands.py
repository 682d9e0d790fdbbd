"""GRW05 Fig. 1 (Example 3, §5.2; also Fig. 2 for Example 4): temperature relaxation.

One panel per particle number n (2 x 2): the confidence band [mean - ci, mean + ci] of the
temperature (GRW05 eq. 31, lambda_p = 3.2; two solid lines) against the analytic solution
(eq. 34, dashed) on the time interval snakemake.params.t_range. The temperature is the
uncentred estimator (1/3)|v|^2, the one behind the paper's tables (RW05 §4.1).
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import numpy as np  # noqa: E402

import granboltz_common as gc  # noqa: E402

plt = gc.pyplot()
runs = sorted((gc.read_run(path) for path in snakemake.input.runs), key=lambda r: r.n)
t_min, t_max = snakemake.params.t_range

ncols = 2 if len(runs) > 1 else 1
nrows = (len(runs) + ncols - 1) // ncols
fig, axes = plt.subplots(nrows, ncols, figsize=(6.3, 2.2 * nrows + 0.3), sharex=True, squeeze=False)
t_fine = np.linspace(t_min, t_max, 400)
for ax, run in zip(axes.flat, runs):
    shown = (run.time >= t_min - 1e-12) & (run.time <= t_max + 1e-12)
    t, mean, ci = run.time[shown], run.T[shown], run.T_ci[shown]
    d = run.config["dsmc"]
    exact = gc.analytic_temperature(
        t_fine, d["initial"]["temperature"], d["alpha"], d["beta"], d["gamma"], d["kernel"]["C"]
    )
    ax.plot(t, mean + ci, "-", color="black", label="confidence interval (31)")
    ax.plot(t, mean - ci, "-", color="black")
    ax.plot(t_fine, exact, color="black", dashes=(4, 2.5), label="analytic solution (34)")
    ax.set_xlim(t_min, t_max)
    ax.text(0.05, 0.92, f"$n = {run.n}$", transform=ax.transAxes, va="top")
    ax.set_ylabel("$T(t)$")
    print(f"n={run.n}: max ci on [{t_min}, {t_max}] = {ci.max():.3g}", file=sys.stderr)
for ax in axes[-1]:
    ax.set_xlabel("$t$")
for ax in axes.flat[len(runs):]:
    ax.set_visible(False)
axes.flat[0].legend(loc="lower right")
fig.tight_layout()
gc.save_figure(fig, [snakemake.output.png, snakemake.output.pdf])
