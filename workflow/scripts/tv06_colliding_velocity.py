"""TV06 Fig. 2 (§3.1): density g_+(v, v1) of the velocity v of the bath particles that hit the
right-hand side of a surface moving at v1, Gaussian bath (eq. 12), one curve per v1 of params.v1.

Analytic (granboltz.theory.colliding_density). The simulator samples this density exactly but does
not output the sampled velocities, so no histogram is overlaid. Checks: each curve integrates to
1 (quadrature), and the mass TV06's sampling windows leave out (v in [v1 - 2, v1] for v1 < 0,
[-3, 3] otherwise, §3.1) is computed for the summary (granboltz.reproduction.tv06_verdicts.
colliding_velocity_verdict).
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import numpy as np  # noqa: E402

from granboltz.output.files import write_csv, write_json  # noqa: E402
from granboltz.output.plotting import figure_summary, pyplot, save_figure  # noqa: E402
from granboltz.theory import colliding_density, colliding_mass  # noqa: E402
from granboltz.reproduction.tv06_verdicts import colliding_velocity_verdict  # noqa: E402

plt = pyplot()
p = snakemake.params
lo, hi = p.v_range
grid = np.round(np.arange(lo, hi + p.table_step / 2, p.table_step), 10)
fine = np.linspace(lo, hi, 1501)

rows, norm_err, missing = [], 0.0, {}
fig, ax = plt.subplots(figsize=(4.6, 3.0))
for k, v1 in enumerate(p.v1):
    for v, g in zip(grid, colliding_density(grid, v1, p.a, p.rho)):
        rows.append({"v1": v1, "v": v, "g_plus": g})
    total = colliding_mass(v1, p.a, -np.inf, np.inf)
    norm_err = max(norm_err, abs(total - 1.0))
    window = (v1 - 2.0, v1) if v1 < 0 else (-3.0, 3.0)
    missing[f"{v1:g}"] = 1.0 - colliding_mass(v1, p.a, *window)
    style = ["-", "--", "-.", ":", (0, (6, 2, 1, 2, 1, 2))][k % 5]
    ax.plot(fine, colliding_density(fine, v1, p.a, p.rho), color="black", ls=style, lw=0.9,
            label=f"$v_1 = {v1:g}$")
ax.set_xlim(lo, hi)
ax.set_ylim(bottom=0)
ax.legend(loc="upper right")
ax.set_xlabel("$v$")
ax.set_ylabel(r"$g_+(v, v_1)$")
fig.tight_layout()
save_figure(fig, [snakemake.output.png, snakemake.output.pdf])
write_csv(rows, ["v1", "v", "g_plus"], snakemake.output.csv, digits=10)

ours, short = colliding_velocity_verdict(p.v1, p.a, p.rho, norm_err, missing)
print(ours, file=sys.stderr)
write_json(figure_summary(ours, short, normalisation_error=norm_err, window_missing_mass=missing),
              snakemake.output.summary)
