"""GRW05 Table 1 (Example 3, §5.2; also Table 2 for Example 4): numerical convergence.

For each run (one per particle number n): E_max, the maximal relative error of the temperature
against the analytic solution (GRW05 eqs. 16/34, 35); CF, the ratio of consecutive E_max
(about 4 for O(1/n)); V_inf, the maximal norm of the bulk velocity; plus our confidence columns
and the error of the centred temperature. The error is that of the uncentred estimator
(1/3)|v|^2, the one the paper used (RW05 §4.1). Columns: granboltz.reproduction.tables.TABLE_COLUMNS.
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from granboltz.reproduction.dsmc import read_dsmc  # noqa: E402
from granboltz.output.files import write_csv  # noqa: E402
from granboltz.reproduction.tables import convergence_rows, TABLE_COLUMNS  # noqa: E402

runs = [read_dsmc(path) for path in snakemake.input.runs]
rows = convergence_rows(runs)
write_csv(rows, TABLE_COLUMNS, snakemake.output.csv)
for row in rows:
    print(", ".join(f"{key}={row[key]}" for key in TABLE_COLUMNS), file=sys.stderr)
