"""GRW05 Figs. 5, 6, 7 (Examples 7, 8, 9, §5.3): logarithmic plot of the steady histogram.

The pairs (x_k, y_k) of GRW05 eq. (38) with k0 = params.tails.k0: x_k = ln(k - k0) with the
shell index k (the paper's fit interval [4.25, 4.6] is beyond ln(r_k - r_k0) <= ln R; the slope
is the same since r_k = k h), y_k = ln(ln f_k0 - ln f_k) with f_k the shell fraction of eq. (37)
divided by the shell volume (params.tails.histogram = density; or the fraction itself); thick
line. Thin guide lines
y = x + c, 1.25 x + c, 1.5 x + c (c = params.guide_intercept: -2, -3, -2 in the paper), and the
least-squares line on params.tails.fit_window (dashed), whose slope b is in the summary
(granboltz.reproduction.grw05_tails.tail_plot_verdict).
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import numpy as np  # noqa: E402

from granboltz.reproduction.dsmc import read_histogram  # noqa: E402
from granboltz.output.files import write_json  # noqa: E402
from granboltz.output.plotting import figure_summary, pyplot, save_figure  # noqa: E402
from granboltz.analysis.tails import fit_tail, tail_points  # noqa: E402
from granboltz.reproduction.grw05_tails import tail_plot_verdict  # noqa: E402

plt = pyplot()
tails, c = snakemake.params.tails, snakemake.params.guide_intercept
(path,) = snakemake.input.runs
hist = read_histogram(path)
k, x, y = tail_points(hist, tails["k0"], tails["min_count"], tails["histogram"])
fit = fit_tail(x, y, tails["fit_window"])
lam = hist["config"]["dsmc"]["kernel"]["lambda"]

fig, ax = plt.subplots(figsize=(4.6, 3.4))
ax.plot(x, y, "-", color="black", lw=1.6, label="$(x_k, y_k)$, eq. (38)")
x_max = np.log(hist["mean"].shape[1] - 1 - tails["k0"])
xs = np.array([0.0, x_max])
for slope in (1.0, 1.25, 1.5):  # thin straight guide lines, labelled near their right end
    ax.plot(xs, slope * xs + c, color="black", lw=0.5)
    x_label = 0.62 * x_max
    ax.annotate(f"$y = {slope:g}x {c:+g}$".replace("= 1x", "= x"), (x_label, slope * x_label + c), xytext=(0, 3),
                textcoords="offset points", ha="right", va="bottom", fontsize=7)
if np.isfinite(fit["b"]):
    lo, hi = tails["fit_window"]
    xw = np.array([lo, hi])
    ax.plot(xw, fit["intercept"] + fit["b"] * xw, color="0.45", lw=3.0, alpha=0.7,
            label=f"fit on [{lo:g}, {hi:g}]: $b = {fit['b']:.3f}$")
ax.set_xlim(0, x_max)
ax.set_ylim(top=max(float(y.max()), 1.5 * x_max + c) + 0.4)
ax.set_xlabel(r"$x_k = \ln(k - k_0)$")
ax.set_ylabel(r"$y_k = \ln(\ln f_{k_0} - \ln f_k)$")
ax.legend(loc="upper left")
fig.tight_layout()
save_figure(fig, [snakemake.output.png, snakemake.output.pdf])

text, short = tail_plot_verdict(snakemake.params.example, lam, fit, tails["fit_window"], x.max(), k.max())
print(text, file=sys.stderr)
write_json(figure_summary(text, short, **fit, x_last=float(x.max()), n=hist["n"], N=hist["N"]),
              snakemake.output.summary)
