"""RW05 Table 1 (§4.1): no-splitting scheme for different n.

For each run (one per n, N ensembles, t in [0, 8]): E_end and E_max, the relative errors of the
temperature against eq. (28) at t_K and over all t_k, Conf_end, the relative confidence
half-width at t_K (lambda_p = 3.2), and their convergence factors CF (quotients of consecutive
rows: about 4 for the errors, O(1/n), and 2 for Conf_end, O(1/sqrt(n))). The temperature is the
uncentred estimator phi(v) = |v|^2/3 that RW05 §4.1 uses. Columns:
granboltz.reproduction.tables.RW05_TABLE1_COLUMNS (the paper's, then ours).
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from granboltz.reproduction.dsmc import read_dsmc  # noqa: E402
from granboltz.output.files import write_csv  # noqa: E402
from granboltz.reproduction.tables import RW05_TABLE1_COLUMNS, rw05_table1_rows  # noqa: E402

runs = [read_dsmc(path) for path in snakemake.input.runs]
rows = rw05_table1_rows(runs)
write_csv(rows, RW05_TABLE1_COLUMNS, snakemake.output.csv)
for row in rows:
    print(", ".join(f"{key}={row[key]}" for key in RW05_TABLE1_COLUMNS), file=sys.stderr)
