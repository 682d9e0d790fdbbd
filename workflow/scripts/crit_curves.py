"""RW05 Figs. 3, 4 (§4.1): the criterion Crit(t) of RW05 eq. (29), deviation from a Maxwellian.

params.label = "n" (Fig. 3): no-splitting runs for several (n, N), one curve each ("from below"
n = 256, 1024, 4096). params.label = "scheme" (Fig. 4): the no-splitting (thick), Strang and
Euler runs (thin) at one n, N, K. params.exact (Fig. 3): also the exact Crit(t) and Crit(inf)
of the moment hierarchy (lambda = 0). Crit is eq. (29) of the ensemble means of the moments
(granboltz.reproduction.dsmc.crit_of_means: it starts from zero for the Maxwellian of eq. 26, as in the
paper; the mean of the per-ensemble Crit, the simulator's /crit, carries a sampling bias of
order 1/sqrt(n) and is only given in the summary). The summary gives Crit(t_end) +- ci
(granboltz.reproduction.dsmc_verdicts.crit_curves_verdict).
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from granboltz.reproduction.dsmc import crit_of_means, read_dsmc  # noqa: E402
from granboltz.reproduction.dsmc_verdicts import crit_curves_verdict  # noqa: E402
from granboltz.output.files import write_json  # noqa: E402
from granboltz.theory.maxwell_hierarchy import crit_exact, crit_steady  # noqa: E402
from granboltz.analysis.moment_checks import hierarchy_physics  # noqa: E402
from granboltz.output.plotting import figure_summary, pyplot, save_figure  # noqa: E402

NAMES = {"nosplit": "no-splitting", "strang": "Strang splitting", "euler": "Euler splitting"}
plt = pyplot()
runs = [read_dsmc(path) for path in snakemake.input.runs]
by_scheme = snakemake.params.label == "scheme"
if not by_scheme:
    runs.sort(key=lambda r: r.n)

fig, ax = plt.subplots(figsize=(4.6, 3.2))
ends, per_ensemble = [], {}
for run, dashes in zip(runs, [(1, 0), (6, 2), (2, 1.5), (4, 1, 1, 1)]):
    crit, ci = crit_of_means(run)
    if by_scheme:
        name = NAMES[run.scheme]
        label = name + ("" if run.dt is None else f", $\\Delta t = {run.dt:g}$")
        style = {"lw": 1.8} if run.scheme == "nosplit" else {"lw": 0.7}
    else:
        name = f"n = {run.n}"
        label, style = f"$n = {run.n}$, $N = {run.N}$", {"lw": 0.9, "dashes": dashes}
    ax.plot(run.time, crit, "-", color="black", label=label, **style)
    ends.append((name, float(crit[-1]), float(ci[-1])))
    per_ensemble[name] = float(run.crit[-1]) if run.crit is not None else None
    print(f"{name}: Crit(t_end) = {crit[-1]:.5f} +- {ci[-1]:.5f}; per-ensemble mean {per_ensemble[name]}",
          file=sys.stderr)
if getattr(snakemake.params, "exact", False):  # Fig. 3 (lambda = 0): the exact Crit(t) and Crit(inf)
    t = runs[0].time
    alpha, beta, nu, T0 = hierarchy_physics(runs[0].config)
    ax.plot(t, crit_exact(t, alpha, beta, nu, T0, d=3), color="0.5", lw=2.2, alpha=0.6, zorder=0, label="exact")
    c_inf = crit_steady(alpha, beta, nu, d=3)
    ax.axhline(c_inf, color="0.5", lw=0.7, ls=":", label=f"exact Crit$(\\infty) = {c_inf:.5f}$")
ax.set_xlim(runs[0].time[0], runs[0].time[-1])
ax.set_ylim(bottom=0)
ax.set_xlabel("$t$")
ax.set_ylabel("Crit$(t)$")
ax.legend(loc="lower right")
fig.tight_layout()
save_figure(fig, [snakemake.output.png, snakemake.output.pdf])

starts = [float(crit_of_means(run)[0][0]) for run in runs]
text, short = crit_curves_verdict(ends, runs[0].time[-1], by_scheme, starts)
write_json(figure_summary(text, short, crit_end={name: [c, ci] for name, c, ci in ends}, per_ensemble=per_ensemble),
              snakemake.output.summary)
