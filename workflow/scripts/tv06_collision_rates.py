"""TV06 Fig. 1 (§3.1): collision rates of a surface moving at v1 in a Gaussian bath.

Left: the total rate phi(v1) = phi_+ + phi_- (eq. 16) for each a of params.a (top to bottom as
a grows, as in the paper); right: phi_+(v1) (solid) and phi_-(v1) (dashed), eq. (15). Closed
forms (granboltz.theory.gaussian_fluxes), checked against quadrature of eqs. (5)-(6), phi(0) =
rho/sqrt(pi a) and phi_+ - phi_- = rho v1. The table has every curve on a grid of params.table_step;
the summary: granboltz.reproduction.tv06_verdicts.collision_rates_verdict.
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import numpy as np  # noqa: E402

from granboltz.output.files import write_csv, write_json  # noqa: E402
from granboltz.output.plotting import figure_summary, pyplot, save_figure  # noqa: E402
from granboltz.theory import fluxes_by_quadrature, gaussian_fluxes  # noqa: E402
from granboltz.reproduction.tv06_verdicts import collision_rates_verdict  # noqa: E402

plt = pyplot()
p = snakemake.params
lo, hi = p.v1_range
grid = np.round(np.arange(lo, hi + p.table_step / 2, p.table_step), 10)
fine = np.linspace(lo, hi, 601)

rows, err_quad, err_zero, err_diff = [], 0.0, 0.0, 0.0
fig, (left, right) = plt.subplots(1, 2, figsize=(6.3, 2.7))
for k, a in enumerate(p.a):
    plus, minus, phi = gaussian_fluxes(grid, a, p.rho)
    for v1, fp, fm, f in zip(grid, plus, minus, phi):
        qp, qm = fluxes_by_quadrature(v1, a, p.rho)
        err_quad = max(err_quad, abs(qp - fp) / max(qp, 1e-8), abs(qm - fm) / max(qm, 1e-8))
        rows.append({"a": a, "v1": v1, "phi_plus": fp, "phi_minus": fm, "phi": f, "phi_plus_quadrature": qp,
                     "phi_minus_quadrature": qm})
    err_zero = max(err_zero, abs(float(gaussian_fluxes(0.0, a, p.rho)[2]) * np.sqrt(np.pi * a) / p.rho - 1))
    err_diff = max(err_diff, float(np.max(np.abs(plus - minus - p.rho * grid))))
    fp, fm, f = gaussian_fluxes(fine, a, p.rho)
    shade = str(0.55 * k / max(1, len(p.a) - 1))
    left.plot(fine, f, color=shade, label=f"$a = {a:g}$")
    right.plot(fine, fp, color=shade, label=f"$a = {a:g}$")
    right.plot(fine, fm, color=shade, dashes=(4, 2))
left.set_ylabel(r"$\phi(v_1)$")
right.set_ylabel(r"$\phi_+(v_1)$ (solid), $\phi_-(v_1)$ (dashed)")
for ax in (left, right):
    ax.set_xlabel("$v_1$")
    ax.set_xlim(lo, hi)
    ax.set_ylim(bottom=0)
left.legend(loc="upper center")
fig.tight_layout()
save_figure(fig, [snakemake.output.png, snakemake.output.pdf])
write_csv(rows, list(rows[0]), snakemake.output.csv, digits=12)

ours, short = collision_rates_verdict(p.a, p.rho, (lo, hi), err_quad, err_zero, err_diff, snakemake.output.csv)
print(ours, file=sys.stderr)
write_json(figure_summary(ours, short, quadrature_rel_error=err_quad, phi0_rel_error=err_zero,
                                difference_error=err_diff), snakemake.output.summary)
