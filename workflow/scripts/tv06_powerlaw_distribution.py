"""TV06 Fig. 5 (§3.1): velocity distributions of the Gillespie intruder (M = params.mass) in the
power-law bath, eq. (19), one per alpha. Left: the density of v1 (bins of params.bin_width) with
the exact solution at alpha = M dashed: the intruder takes the colliding velocity (eq. 17), so its
distribution is the bath's f(v, a) itself (T = M <v1^2> = alpha T_B); it is checked bin by bin
(granboltz.reproduction.tv06_histograms.histogram_check, |v1| <= check_range). Right (the paper's inset):
log-log density of |v1| with a v^-4 guide; least-squares exponents on tail_window (theory -4).
Summary: granboltz.reproduction.tv06_verdicts.powerlaw_distribution_verdict.
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import numpy as np  # noqa: E402

from granboltz.output.files import write_csv, write_json  # noqa: E402
from granboltz.output.plotting import figure_summary, pyplot, save_figure  # noqa: E402
from granboltz.theory import exact_temperature_ratio, powerlaw_pdf  # noqa: E402
from granboltz.reproduction.tv06_histograms import folded_tail, histogram_check, rebin, tail_exponent  # noqa: E402
from granboltz.reproduction.tv06_tables import read_tv06  # noqa: E402
from granboltz.reproduction.tv06_verdicts import powerlaw_distribution_verdict  # noqa: E402

plt = pyplot()
p = snakemake.params
runs = sorted((read_tv06(path) for path in snakemake.input.runs), key=lambda r: r["alpha"])
if any(r["model"] != "intruder" or r["bath"] != "powerlaw" or r["M"] != p.mass or r["histogram"] is None for r in runs):
    raise ValueError(f"Fig. 5 needs power-law intruder runs with histograms at M = {p.mass}")
a = runs[0]["a"]
exact = lambda v: powerlaw_pdf(v, a)  # noqa: E731

fig, (left, right) = plt.subplots(1, 2, figsize=(6.6, 3.0))
cmap = plt.matplotlib.colors.ListedColormap(plt.cm.viridis(np.linspace(0.0, 0.9, 256)))  # alpha -> colour
colours = cmap([r["alpha"] for r in runs])
rows, fits, check, peaks = [], {}, None, []
for run, colour in zip(runs, colours):
    h, al = run["histogram"], run["alpha"]
    known = exact_temperature_ratio("powerlaw", al, p.mass) is not None
    v, d, ci = rebin(h, int(round(p.bin_width / (h["edges"][1] - h["edges"][0]))))
    shown = np.abs(v) <= p.v_max
    left.plot(v[shown], d[shown], color=colour, lw=0.8)
    peaks.append(float(d[shown].max()))
    vt, dt, ct = folded_tail(h, p.tail_from)
    many = ct >= 10  # drawn: log bins with at least 10 samples
    right.loglog(vt[many], dt[many], ".-", color=colour, lw=0.6, ms=2)
    fits[f"{al:g}"] = tail_exponent(vt, dt, ct, p.tail_window)
    rows += [{"alpha": al, "panel": panel, "v": x, "density": y, "ci": c, "samples": n,
              "exact": float(exact(x)) if known else None}
             for panel, xs, ys, cs, ns in (("linear", v[shown], d[shown], ci[shown], [None] * shown.sum()),
                                           ("tail", vt, dt, [None] * vt.size, ct.astype(int)))
             for x, y, c, n in zip(xs, ys, cs, ns)]
    if known:
        check = dict(alpha=al, **histogram_check(h, exact, p.check_range, run["N"]))
        vs = np.linspace(-p.v_max, p.v_max, 400)
        left.plot(vs, exact(vs), color="red", dashes=(3, 2), lw=1.0, zorder=5, label=f"exact at $\\alpha = M = {al:g}$")
        vs = np.geomspace(p.tail_from, vt[many].max(), 200)
        right.loglog(vs, exact(vs), color="red", dashes=(3, 2), lw=1.0, zorder=5)
vg = np.array(p.tail_window)
right.loglog(vg, 0.3 * exact(vg[0]) * (vg / vg[0]) ** -4.0, color="black", lw=1.6, label=r"$\propto v^{-4}$")
left.set(xlim=(-p.v_max, p.v_max), ylim=(0, None), xlabel="$v_1$", ylabel="$f(v_1)$")
right.set(xlabel=r"$|v_1|$", ylabel=r"$f(|v_1|)$")
left.legend(loc="upper right", fontsize=7)
right.legend(loc="lower left")
fig.tight_layout()
fig.colorbar(plt.cm.ScalarMappable(cmap=cmap, norm=plt.Normalize(0, 1)), ax=[left, right], fraction=0.03, pad=0.02,
             label=r"$\alpha$")
save_figure(fig, [snakemake.output.png, snakemake.output.pdf])
write_csv(rows, ["alpha", "panel", "v", "density", "ci", "samples", "exact"], snakemake.output.csv, digits=6)

ours, short = powerlaw_distribution_verdict(fits, peaks, check, p.tail_window, runs[0]["N"], snakemake.output.csv)
print(ours, file=sys.stderr)
write_json(figure_summary(ours, short, exponents=fits, check=check), snakemake.output.summary)
