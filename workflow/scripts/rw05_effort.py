"""RW05 §4.2 (efficiency): the effort model against the counted events of the steady runs.

For every steady run (no-splitting, Euler and Strang for each K of Tables 3, 4): the predicted
mean numbers of collisions N_coll = 2(n - 1) s_M and of kicks (no-splitting 2 N_coll + n M,
splitting s_M n / dt), the counted ones (/events, mean per ensemble), the effort N_coll + N_kick
relative to no-splitting (model and counted) and the measured CPU ratio (/provenance
wall_seconds). Columns: granboltz.reproduction.steady.EFFORT_COLUMNS.
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from granboltz.reproduction.dsmc import read_steady  # noqa: E402
from granboltz.output.files import write_csv  # noqa: E402
from granboltz.reproduction.steady import EFFORT_COLUMNS, effort_rows  # noqa: E402

steadies = [read_steady(path) for path in dict.fromkeys(snakemake.input.runs)]
rows = effort_rows(steadies, snakemake.params.dt_unit, snakemake.params.steady_from)
write_csv(rows, EFFORT_COLUMNS, snakemake.output.csv, digits=6)
for row in rows:
    print(row, file=sys.stderr)
