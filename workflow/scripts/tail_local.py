"""GRW05 Examples 7-9 (§5.3): the local tail exponent b(r), free of the core's offset.

b(r) = 1 + d ln(-d_r ln f)/d ln r on sliding windows of pooled shells, with its band (z = 3.2,
the delta method), against the theory b = 1 + lambda/2 (tail_theory) and against b(r) of the
theory tail r^chi exp(-a r^b) with a, chi fitted at that b (dashed); shaded: the paper's eq. (38)
window and the configured one (x = ln(k - k0) in r); dotted: where the data run out
(local_exponent.data_limit).  Summary: granboltz.analysis.tail_local.SUMMARY_KEYS and the verdict
(granboltz.reproduction.grw05_tails.tail_local_verdict).
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import numpy as np  # noqa: E402

from granboltz.reproduction.dsmc import read_histogram  # noqa: E402
from granboltz.output.files import write_json  # noqa: E402
from granboltz.analysis.local_exponent import shells_from_h5  # noqa: E402
from granboltz.output.plotting import figure_summary, pyplot, save_figure  # noqa: E402
from granboltz.analysis.tail_local import local_tail_summary, model_local_exponent, window_radii  # noqa: E402
from granboltz.reproduction.grw05_tails import tail_local_verdict  # noqa: E402

plt = pyplot()
tails, example = snakemake.params.tails, snakemake.params.example
(path,) = snakemake.input.runs
hist = read_histogram(path)
lam = float(hist["config"]["dsmc"]["kernel"]["lambda"])
shells = shells_from_h5(path)
s, curve = local_tail_summary(shells, float(hist["T"][-1]), lam, example, tails["local"], tails["fit_window"],
                              tails["k0"])
R, K = float(shells["edges"][-1]), len(shells["frac"])

fig, ax = plt.subplots(figsize=(4.6, 3.4))
ok = ~curve["at_bound"]
r, b, ci = curve["r"][ok], curve["b"][ok], curve["ci_b"][ok]
ax.fill_between(r, b - ci, b + ci, color="0.8", lw=0, label="band ($z = 3.2$)")
ax.plot(r, b, "-", color="black", lw=1.2, label="local exponent $b(r)$")
ax.axhline(s["theory_b"], color="black", lw=0.7, ls="-.", label=f"theory $b = {s['theory_b']:g}$")
rs = np.linspace(max(r.min(), 0.5), s["r_limit"], 200)
ax.plot(rs, model_local_exponent(s["a_fit"], s["theory_b"], s["chi_fit"], rs), "--", color="0.3", lw=0.9,
        label=f"theory tail, $\\chi = {s['chi_fit']:.2f}$")
for window, shade, name in ((tails["local"]["paper_window"], "0.55", "paper's window"),
                            (tails["fit_window"], "0.85", "our fit window")):
    lo, hi = window_radii(window, R, K, tails["k0"])
    ax.axvspan(lo, hi, color=shade, alpha=0.25, lw=0, label=name)
ax.axvline(s["r_limit"], color="black", ls=":", lw=0.9, label="data run out")
ax.plot([s["r_far"]], [s["b_local_far"]], "o", color="black", ms=4)
ax.set_xlim(0, max(R, s["r_limit"]))
ax.set_ylim(0.5, 2.5)
ax.set_xlabel("$r = |v|$")
ax.set_ylabel("$b(r)$")
ax.legend(loc="upper right", fontsize=6.5)
fig.tight_layout()
save_figure(fig, [snakemake.output.png, snakemake.output.pdf])

text, short = tail_local_verdict(s, example, lam)
print(text, file=sys.stderr)
write_json(figure_summary(text, short, **s, curve={k: curve[k].tolist() for k in ("r", "b", "ci_b")}),
           snakemake.output.summary)
