"""RW05 Table 2 (§4.1): Euler- and Strang-splitting schemes for n = 4096.

For each K (time step dt = 8/K): E_max, the maximal relative error of the temperature
(uncentred estimator, observed at every t_k = k dt) against eq. (28), for the Euler and the
Strang scheme, with convergence factors CF (about 2: first order; about 4: second order).
Our columns add the confidence half-widths at the maximal error and E_expected, the exact
systematic error of each scheme (time step and finite n; granboltz.theory.expected_error).
Columns: granboltz.reproduction.tables.RW05_TABLE2_COLUMNS.
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from granboltz.reproduction.dsmc import read_dsmc  # noqa: E402
from granboltz.output.files import write_csv  # noqa: E402
from granboltz.reproduction.tables import RW05_TABLE2_COLUMNS, timestep_rows  # noqa: E402

euler = [read_dsmc(path) for path in snakemake.input.euler]
strang = [read_dsmc(path) for path in snakemake.input.strang]
rows = timestep_rows(euler, strang, snakemake.params.dt_unit)  # K = dt_unit / dt
write_csv(rows, RW05_TABLE2_COLUMNS, snakemake.output.csv)
for row in rows:
    print(", ".join(f"{key}={row[key]}" for key in RW05_TABLE2_COLUMNS), file=sys.stderr)
