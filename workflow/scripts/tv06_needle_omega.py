"""TV06 Fig. 8 (§3.2): angular-velocity distribution of the needle at M = 0.1, alpha = 0.1
(the paper: 5 000 000 collisions), black, with the best-fit Gaussian, red.

Best fit: A exp(-w^2 / (2 s^2)) by unweighted least squares on the histogram density
(scipy.optimize.curve_fit; amplitude and width free, as a fitted curve on a plot); dashed grey:
the moment-matched normal density (variance of the histogram). Left linear, right logarithmic
(the tails). The grey band is the 99.9 % confidence interval of the density over the N ensembles.
The summary counts the bins whose interval excludes the fitted Gaussian (the deviations the
paper calls 'apparent'; resolved when that count has binomial p < 0.001 against an exact curve)
and gives the excess kurtosis (granboltz.reproduction.tv06_verdicts.needle_omega_verdict).
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import numpy as np  # noqa: E402

from granboltz.output.files import write_csv, write_json  # noqa: E402
from granboltz.output.plotting import figure_summary, pyplot, save_figure  # noqa: E402
from granboltz.theory import LAMBDA_P  # noqa: E402
from granboltz.reproduction.tv06_histograms import gaussian_fits  # noqa: E402
from granboltz.reproduction.tv06_tables import read_tv06  # noqa: E402
from granboltz.reproduction.tv06_verdicts import needle_omega_verdict  # noqa: E402

plt = pyplot()
(run,) = [read_tv06(path) for path in snakemake.input.runs]
h = run["omega"]
if run["model"] != "needle" or h is None:
    raise ValueError(f"{run['path']}: Fig. 8 needs a needle run with an omega histogram")
g = gaussian_fits(h)
w, d, ci = g["centres"], h["density"], h["ci"]
z = (d - g["fit"]) / np.where(ci > 0, ci / LAMBDA_P, np.inf)
rows = [{"omega": x, "density": y, "ci": c, "gaussian_fit": f, "gaussian_moments": m, "z_fit": zz}
        for x, y, c, f, m, zz in zip(w, d, ci, g["fit"], g["moments"], z)]
write_csv(rows, list(rows[0]), snakemake.output.csv, digits=6)

fig, axes = plt.subplots(1, 2, figsize=(6.4, 2.8))
for ax in axes:
    ax.fill_between(w, d - ci, d + ci, color="0.8", lw=0, label="99.9 % CI")
    ax.plot(w, d, color="black", lw=0.9, label=f"simulation, {run['N'] * run['collisions']:,} collisions")
    ax.plot(w, g["fit"], color="red", lw=0.9, label="best-fit Gaussian")
    ax.plot(w, g["moments"], color="0.4", lw=0.8, dashes=(3, 2), label="Gaussian, same variance")
    ax.set_xlabel(r"$\omega$")
    ax.set_xlim(-1.05 * np.abs(w[h["counts"] > 0]).max(), 1.05 * np.abs(w[h["counts"] > 0]).max())
axes[0].set_ylabel(r"$P(\omega)$")
axes[1].set_yscale("log")
axes[1].set_ylim(max(d[d > 0].min(), 1e-6) / 2, d.max() * 2)
axes[1].legend(loc="lower center", fontsize=6)
fig.tight_layout()
save_figure(fig, [snakemake.output.png, snakemake.output.pdf])

_, ours, short, numbers = needle_omega_verdict(run, g, z, ci, snakemake.output.csv)
print(ours, file=sys.stderr)
write_json(figure_summary(ours, short, **numbers), snakemake.output.summary)
