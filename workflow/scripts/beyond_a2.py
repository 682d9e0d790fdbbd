"""Beyond the papers: the Sonine coefficient a2(alpha) of the steady states of both
thermostats, side by side.  Gaussian thermostat: the homogeneous cooling state in scaled
velocities; hard spheres against van Noije-Ernst's first-Sonine formula, Maxwell molecules
against the exact HCS value of the moment hierarchy (granboltz.maxwell_hierarchy.hcs_a2).
White noise: hard spheres against van Noije-Ernst's heated formula, Maxwell molecules against
the exact steady value.  a2 = <fourth_moment>/(15 <T>^2) over the steady observations.
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import numpy as np  # noqa: E402

from granboltz import read_run  # noqa: E402
from granboltz.beyond import a2_rows, a2_verdict, theory_a2  # noqa: E402
from granboltz.files import write_csv, write_json  # noqa: E402
from granboltz.plotting import figure_summary, pyplot, save_figure  # noqa: E402

p = snakemake.params
rows = a2_rows([read_run(path) for path in snakemake.input.runs], p.rel_tol, p.abs_floor)
columns = ["thermostat", "kernel", "alpha", "n", "N", "a2", "ci", "theory", "theory_kind", "diff", "z", "rel_diff",
           "tol", "agrees", "published", "published_source"]
write_csv(rows, columns, snakemake.output.csv, digits=5)

plt = pyplot()
fig, axes = plt.subplots(1, 2, figsize=(6.3, 2.9))
alpha_fine = np.linspace(0.15, 1.0, 200)
titles = {"gaussian": "Gaussian thermostat (HCS)", "white_noise": "white noise (steady)"}
for ax, thermostat in zip(axes, ("gaussian", "white_noise")):
    for kernel, lam, marker, style, label in (("hard_spheres", 1, "s", "--", "hard spheres; van Noije–Ernst"),
                                              ("maxwell", 0, "o", "-", "Maxwell molecules; exact")):
        mine = [r for r in rows if r["thermostat"] == thermostat and r["kernel"] == kernel]
        curve = [theory_a2(thermostat, lam, float(a)) for a in alpha_fine]
        ax.plot(alpha_fine, [c[0] for c in curve], style, color="black", label=label)
        if mine:
            ax.errorbar([r["alpha"] for r in mine], [r["a2"] for r in mine], yerr=[r["ci"] for r in mine],
                        fmt=marker, ms=3.5, mfc="none", color="black", capsize=1.5)
    ax.axhline(0.0, color="grey", lw=0.4)
    ax.set_title(titles[thermostat])
    ax.set_xlabel("$\\alpha$")
axes[0].set_ylabel("$a_2$")
axes[0].set_ylim(-0.05, 1.0)  # Maxwell HCS: a2 -> 2 as alpha -> 0 (power-law tail)
axes[1].legend(loc="upper right", fontsize=7)
save_figure(fig, [snakemake.output.png, snakemake.output.pdf])

checks = [("gaussian", "maxwell", None), ("gaussian", "hard_spheres", None), ("white_noise", "maxwell", None),
          ("white_noise", "hard_spheres", p.key_alphas)]
verdicts = {(t, k): a2_verdict(rows, t, k, a) for t, k, a in checks}
ok = all(v[0] for v in verdicts.values())
ours = "; ".join(f"{t.replace('_', ' ')}, {k.replace('_', ' ')}: {text}" for (t, k), (_, text) in verdicts.items())
short = ("agrees" if ok else "differs") + " (" + "; ".join(
    f"{t.replace('_', ' ')} {k.replace('_', ' ')} {'agrees' if v[0] else 'differs'}" for (t, k), v in verdicts.items()) + ")"
write_json(figure_summary(ours, short, ok=ok), snakemake.output.summary)
print(ours, file=sys.stderr)
