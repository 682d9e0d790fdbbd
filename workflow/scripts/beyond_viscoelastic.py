"""Beyond the papers: free cooling of viscoelastic hard spheres, T ~ t^(-5/3) at late times
(Brilliantov & Pöschel), not Haff's t^(-2); and the elastic limit delta = 0, T constant.
Theory, rows and verdict: granboltz.reproduction.viscoelastic (the Maxwellian moment equation with the full law).
Writes the table (log-spaced times: T, theory, local slope, a2), the figure (T on log-log axes with
the theory; below, the local slope d ln T/d ln t against -5/3 and -2, the late-window fit) and the
summary with the computed verdict.
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import numpy as np  # noqa: E402

from granboltz import read_run  # noqa: E402
from granboltz.reproduction import viscoelastic as ve  # noqa: E402
from granboltz.output.files import write_csv, write_json  # noqa: E402
from granboltz.output.plotting import figure_summary, pyplot, save_figure  # noqa: E402

runs = [read_run(path) for path in snakemake.input.runs]
rows = ve.viscoelastic_rows(runs, snakemake.params.rows, snakemake.params.late_from)
write_csv(rows, ["delta", "n", "N", "t", "t_over_tau0", "T", "ci", "T_theory", "rel_theory", "slope", "slope_ci",
                 "slope_theory", "a2", "a2_ci", "late"], snakemake.output.csv, digits=6)
ok, fits, text = ve.viscoelastic_verdict(rows)

plt = pyplot()
fig, (top, bottom, zoom) = plt.subplots(3, 1, figsize=(6.3, 7.0), sharex=True,
                                       gridspec_kw={"height_ratios": [3, 2, 2]})
markers = iter("osd^v")
for fit in fits:
    delta, marker = fit["delta"], next(markers)
    mine = [r for r in rows if r["delta"] == delta]
    run = next(r for r in runs if ve.run_delta(r) == delta)
    d = run.config["dsmc"]
    n, T0, g, C = d["particles"], d["initial"]["temperature"], d["gamma"], d["kernel"]["C"]
    t = np.array([r["t"] for r in mine])
    grid = np.geomspace(t[0] / 3, t[-1], 200)
    curve = ve.free_cooling_temperature(grid, delta, T0 * (1 - 1 / n), g, C, n)
    top.loglog(grid, curve, "-", color="black", lw=0.8)
    top.loglog(grid, ve.asymptotic_temperature(grid, delta, T0 * (1 - 1 / n), g, C, n), ":", color="black", lw=0.8)
    top.errorbar(t, [r["T"] for r in mine], yerr=[r["ci"] for r in mine], fmt=marker, ms=3, mfc="none",
                 color="black", label=f"δ = {delta:g} ($\\tau_0$ = {ve.tau0(delta, T0, g, C, n):.3g})")
    mid = np.sqrt(t[1:] * t[:-1])  # each local slope spans the previous row to this one
    for ax in (bottom, zoom):
        ax.semilogx(grid, ve.local_slope(grid, curve, delta, g, C, n), "-", color="black", lw=0.8)
        ax.errorbar(mid, [r["slope"] for r in mine[1:]], yerr=[r["slope_ci"] for r in mine[1:]], fmt=marker, ms=3,
                    mfc="none", color="black", lw=0.5)
        ax.errorbar([np.sqrt(fit["t_min"] * fit["t_max"])], [fit["value"]], yerr=[fit["ci"]], fmt=marker, ms=6,
                    color="black", capsize=3)
elastic = [r for r in rows if r["delta"] == 0]
if elastic:
    top.loglog([r["t"] for r in elastic], [r["T"] for r in elastic], "x", ms=3, color="black", label="δ = 0 (elastic)")
top.plot([], [], "-", color="black", lw=0.8, label="moment equation, full law")
top.plot([], [], ":", color="black", lw=0.8, label="$T_0[1 + (3/5)t/\\tau_0]^{-5/3}$")
top.set_ylabel("$T(t)$")
top.legend(fontsize=7)
for ax, lines in ((bottom, ((-5 / 3, "--", "$-5/3$"), (-2.0, "-.", "Haff $-2$"))), (zoom, ((-5 / 3, "--", "$-5/3$"),))):
    for value, style, name in lines:
        ax.axhline(value, ls=style, color="gray", lw=0.8)
        ax.text(ax.get_xlim()[0] * 1.2, value + 0.004, name, fontsize=7, color="gray")
    ax.axvspan(fits[0]["t_min"], fits[0]["t_max"], color="0.9", zorder=0)
    ax.set_ylabel("$d\\ln T/d\\ln t$")
bottom.set_ylim(-2.1, -0.8)
zoom.set_ylim(-1.76, -1.60)  # the late slopes: -5/3 and the approach to it
zoom.set_xlabel("$t$ (shaded: the late window of the slope fit, large markers)")
save_figure(fig, [snakemake.output.png, snakemake.output.pdf])

short = ve.short_verdict(ok, fits)
write_json(figure_summary(text, short, ok=ok, fits=fits), snakemake.output.summary)
print(text, file=sys.stderr)
