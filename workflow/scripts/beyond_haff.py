"""Beyond the papers: Haff's law.  Free cooling (thermostat none) of Maxwell molecules,
T(t) = T0 e^{-gamma pi C (1 - alpha^2) t} exactly (GRW05 eq. 16 with beta = 0), and of hard
spheres, T(t) = T0/(1 + t/t0)^2 with t0 from the cooling rate with the first-Sonine a2 of the HCS
(granboltz.reproduction.beyond.haff_temperature; both with the centred estimator's factor 1 - 1/n).
Writes the table (every observation, its sigma-distance), the figure (T on a log scale with its
band; below, the ratio to the theory) and the summary with the verdict of
granboltz.reproduction.beyond.haff_item_verdict.
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import numpy as np  # noqa: E402

from granboltz import read_run  # noqa: E402
from granboltz.reproduction.beyond import haff_item_verdict, haff_rows  # noqa: E402
from granboltz.output.files import write_csv, write_json  # noqa: E402
from granboltz.output.plotting import figure_summary, pyplot, save_figure  # noqa: E402

runs = [read_run(path) for path in snakemake.input.runs]
rows = haff_rows(runs)
write_csv(rows, ["kernel", "alpha", "n", "N", "t", "T", "ci", "T_theory", "ratio", "z"], snakemake.output.csv, digits=6)

plt = pyplot()
fig, (top, bottom) = plt.subplots(2, 1, figsize=(6.3, 4.6), sharex=False, gridspec_kw={"height_ratios": [2, 1]})
labels = {"maxwell": "Maxwell molecules, $e^{-\\gamma\\pi C(1-\\alpha^2)t}$",
          "hard_spheres": "hard spheres, Haff $T_0/(1+t/t_0)^2$"}
for kernel, marker in (("maxwell", "o"), ("hard_spheres", "s")):
    mine = [r for r in rows if r["kernel"] == kernel]
    if not mine:
        continue
    t = np.array([r["t"] for r in mine])
    T, ci, th = (np.array([r[k] for r in mine]) for k in ("T", "ci", "T_theory"))
    t_max = t[-1]  # each kernel on its own time scale: t / t_end
    top.semilogy(t / t_max, th, "-", color="black", lw=0.8)
    top.errorbar(t / t_max, T, yerr=ci, fmt=marker, ms=3, mfc="none", color="black", label=labels[kernel])
    bottom.errorbar(t / t_max, T / th - 1, yerr=ci / th, fmt=marker, ms=3, mfc="none", color="black")
top.set_ylabel("$T(t)$")
top.legend()
bottom.axhline(0.0, color="black", lw=0.6)
bottom.set_xlabel("$t/t_\\mathrm{end}$ (Maxwell: $t_\\mathrm{end}$ = %g; hard spheres: %g)"
                  % tuple(max(r["t"] for r in rows if r["kernel"] == k) for k in ("maxwell", "hard_spheres")))
bottom.set_ylabel("$T/T_\\mathrm{theory} - 1$")
save_figure(fig, [snakemake.output.png, snakemake.output.pdf])

ok, ours, short = haff_item_verdict(rows)
write_json(figure_summary(ours, short, ok=ok), snakemake.output.summary)
print(ours, file=sys.stderr)
