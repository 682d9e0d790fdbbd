"""Transport and rheology: the table shear_rheology (granboltz.rheology), its figure (P_ij/p
against alpha beside the exact lambda = 0 or Grad values) and the summary with the verdict
computed by granboltz.reproduction.rheology.rheology_verdict."""

import math
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from granboltz import read_run  # noqa: E402
from granboltz.output.files import write_csv, write_json  # noqa: E402
from granboltz.output.plotting import figure_summary, pyplot, save_figure  # noqa: E402
from granboltz.reproduction.rheology import COLUMNS, RHEOLOGY_COMPONENTS, rheology_verdict, shear_rheology  # noqa: E402

frame = shear_rheology([read_run(p) for p in snakemake.input.runs])
rows = frame.to_dict("records")
# empty where a column does not apply (d = 2 has no zz, free hard spheres no exact values)
write_csv([{k: (None if isinstance(v, float) and math.isnan(v) else v) for k, v in r.items()} for r in rows],
          COLUMNS, snakemake.output.csv, digits=5)

plt = pyplot()
fig, axes = plt.subplots(1, 4, figsize=(9.0, 2.8), sharex=True)
styles = {("maxwell", "gaussian"): "grey", ("hard_spheres", "gaussian"): "black", ("hard_spheres", "none"): "tab:blue"}
for ax, name in zip(axes, RHEOLOGY_COMPONENTS):
    for r in rows:
        colour = styles.get((r["model"], r["thermostat"]), "black")
        ax.errorbar([r["alpha"] + 0.02 * r["shear_rate"]], [r[f"P{name}_p"]], yerr=[r[f"P{name}_p_ci"]], fmt="o", ms=3,
                    mfc="none", color=colour, capsize=1.5)
        ax.plot([r["alpha"] + 0.02 * r["shear_rate"]], [r[f"P{name}_p_theory"]], "x", color=colour, ms=4)
    ax.set_title(f"$P_{{{name}}}/p$", fontsize=8)
    ax.set_xlabel("$\\alpha$")
save_figure(fig, [snakemake.output.png, snakemake.output.pdf])

ours, short, kind = rheology_verdict(rows)
write_json(figure_summary(ours, short, kind=kind, rows=len(rows)), snakemake.output.summary)
print(ours, file=sys.stderr)
