"""Beyond the papers: the Sonine coefficient a2(alpha) of the steady states of both
thermostats, side by side.  Gaussian thermostat: the homogeneous cooling state in scaled
velocities; hard spheres against van Noije-Ernst's first-Sonine formula, Maxwell molecules
against the exact HCS value of the moment hierarchy (granboltz.theory.maxwell_hierarchy.hcs_a2).
White noise: hard spheres against van Noije-Ernst's heated formula, Maxwell molecules against
the exact steady value.  a2 = <fourth_moment>/(15 <T>^2) over the steady observations.  Beside
it: the second Sonine a2 and a3 of hard spheres, the simulator's steady a3, and the exact a3 of
Maxwell molecules; the figure shows a2 (top) and a3 (bottom) among the approximations.
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import numpy as np  # noqa: E402

from granboltz import read_run  # noqa: E402
from granboltz.reproduction.beyond import a2_item_verdict, a2_rows, theory_a2  # noqa: E402
from granboltz.theory.sonine import hcs_moment_threshold, maxwell_a3, second_sonine  # noqa: E402
from granboltz.output.files import write_csv, write_json  # noqa: E402
from granboltz.output.plotting import figure_summary, label_sonine_panels, pyplot, save_figure  # noqa: E402

p = snakemake.params
rows = a2_rows([read_run(path) for path in snakemake.input.runs], p.rel_tol, p.abs_floor)
columns = ["thermostat", "kernel", "alpha", "n", "N", "a2", "ci", "theory", "theory_kind", "diff", "z", "rel_diff",
           "tol", "agrees", "published", "published_source", "a2_second_sonine", "a3", "a3_ci", "a3_second_sonine",
           "a3_exact", "a3_valid"]
write_csv(rows, columns, snakemake.output.csv, digits=5)

plt = pyplot()
fig, axes = plt.subplots(2, 2, figsize=(6.3, 5.2), sharex=True)
alpha_fine = np.linspace(0.15, 1.0, 200)
for col, thermostat in enumerate(("gaussian", "white_noise")):
    top, bottom = axes[0, col], axes[1, col]
    s2, s3 = second_sonine(alpha_fine, thermostat, d=3)
    top.plot(alpha_fine, [theory_a2(thermostat, 1, float(a), 3)[0] for a in alpha_fine], "--", color="black",
             label="hard spheres (squares): first Sonine (vNE)")
    top.plot(alpha_fine, s2, ":", color="black", label="hard spheres: second Sonine")
    top.plot(alpha_fine, [theory_a2(thermostat, 0, float(a), 3)[0] for a in alpha_fine], "-", color="black",
             label="Maxwell molecules (circles): exact")
    bottom.plot(alpha_fine, s3, ":", color="black")
    exact3 = np.array([maxwell_a3(float(a), thermostat, d=3) for a in alpha_fine], dtype=float)
    bottom.plot(alpha_fine, exact3, "-", color="black")
    for kernel, marker in (("hard_spheres", "s"), ("maxwell", "o")):
        mine = [r for r in rows if r["thermostat"] == thermostat and r["kernel"] == kernel]
        if not mine:
            continue
        top.errorbar([r["alpha"] for r in mine], [r["a2"] for r in mine], yerr=[r["ci"] for r in mine],
                     fmt=marker, ms=3.5, mfc="none", color="black", capsize=1.5)
        # a3 intervals only where they are valid (the Maxwell HCS needs <c^12> finite)
        shown = [r for r in mine if r["a3_valid"]]
        bottom.errorbar([r["alpha"] for r in shown], [r["a3"] for r in shown], yerr=[r["a3_ci"] for r in shown],
                        fmt=marker, ms=3.5, mfc="none", color="black", capsize=1.5)
    if thermostat == "gaussian":
        bottom.axvline(hcs_moment_threshold(6, d=3), color="grey", lw=0.4, ls="--")
label_sonine_panels(axes)
axes[0, 0].set_ylim(-0.05, 1.0)  # Maxwell HCS: a2 -> 2 as alpha -> 0 (power-law tail)
axes[1, 0].set_ylim(-0.1, 0.3)
axes[1, 1].set_ylim(-0.03, 0.03)
axes[0, 1].legend(loc="upper right", fontsize=6.5)
save_figure(fig, [snakemake.output.png, snakemake.output.pdf])

kind, ours = a2_item_verdict(rows)
write_json(figure_summary(ours, ours, kind=kind), snakemake.output.summary)
print(ours, file=sys.stderr)
