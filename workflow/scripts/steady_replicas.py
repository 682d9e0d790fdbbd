"""RW05 Tables 3-6 (§4.2), our check of their confidence intervals: repeated steady runs.

Tables 3-6 give Conf, the confidence half-width of T_inf from the M = 64 observations of one
run, taken as independent ("big enough to assure almost independent observations"). Here the
no-splitting run (input nosplit) and one Euler run (input euler) are repeated with other seeds:
the sample standard deviation of their T_inf against the nominal sigma = Conf / lambda_p and
against the batch estimator's sigma of one run, the mean against the exact expectation
T_expected, and the lag-1 autocorrelation of the observations. Columns:
granboltz.reproduction.steady.REPLICA_COLUMNS.
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from granboltz.reproduction.dsmc import read_steady  # noqa: E402
from granboltz.output.files import write_csv  # noqa: E402
from granboltz.reproduction.steady import REPLICA_COLUMNS, replica_rows  # noqa: E402

groups = [[read_steady(path) for path in paths] for paths in (snakemake.input.nosplit, snakemake.input.euler)]
rows = replica_rows(groups, snakemake.params.dt_unit)
write_csv(rows, REPLICA_COLUMNS, snakemake.output.csv, digits=6)
for row in rows:
    print(row, file=sys.stderr)
