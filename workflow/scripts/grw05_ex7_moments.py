"""GRW05 Example 7 (§5.3, lambda = 0): the speed moments M_2 ... M_2P of the final state against
the exact moment hierarchy (granboltz.analysis.moment_checks, maxwell_hierarchy).

P = params.moments (8: M_2 ... M_16; the run may hold more).
Output csv: p, exact (M_2p at t_end from the initial Maxwellian: the exact time-dependent value),
ours (/moment_2p, ensemble mean), ci (its half-width, lambda_p = 3.2), sigma ((ours - exact)/se),
exact_steady (the steady value; the difference shows how far the state has relaxed).
Output amplitude: the tail amplitude a from the growth of the exact steady moments
M_{2p+2}/M_2p, p = 0..params.pmax, against sqrt(nu/beta) (tails.md; tail_theory).
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from granboltz.output.files import write_csv  # noqa: E402
from granboltz.analysis.moment_checks import (AMPLITUDE_COLUMNS, MOMENT_COLUMNS, amplitude_rows,  # noqa: E402
                                     hierarchy_physics, moment_rows, moment_verdict, read_speed_moments)

(path,) = snakemake.input.runs
config, t, means, cis = read_speed_moments(path)
P = snakemake.params.moments
if len(means) < P:
    raise ValueError(f"{path}: holds M_2 ... M_{2 * len(means)}, need M_{2 * P} (set dsmc moments >= {P})")
means, cis = means[:P], cis[:P]
alpha, beta, nu, T0 = hierarchy_physics(config)
rows = moment_rows(means, cis, alpha, beta, nu, T0, t)
write_csv(rows, MOMENT_COLUMNS, snakemake.output.csv, digits=7)
write_csv(amplitude_rows(alpha, beta, nu, snakemake.params.pmax), AMPLITUDE_COLUMNS, snakemake.output.amplitude,
          digits=6)
for row in rows:
    print(row, file=sys.stderr)
print(moment_verdict(rows), file=sys.stderr)
