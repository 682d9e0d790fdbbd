"""RW05 Tables 3, 4, 5 and 6 (§4.2): approximation of the stationary temperature.

One long run per scheme (n = 65536): T_inf, the average of the uncentred temperature |v|^2/3
over the observations s_m > s0 (the simulator's /steady); Error = |T_inf - T_exact| (T_exact =
8/3, or 100 for Table 6, eq. 25); Conf, the confidence half-width over the M observations taken as
independent (the paper's); Conf_batch, the honest one of the same run (/steady/.../batch); CPU,
the simulator's wall time (/provenance wall_seconds; one thread) relative to the no-splitting run
(input nosplit); CF: quotients of consecutive rows. params.layout: "steps" (Tables 3, 4: one row
per K), "single" (Table 5), "methods" (Table 6: one row per scheme). Ours add T_scheme, the
scheme's exact stationary value (n -> infinity), and T_expected, with the estimator's finite-n bias.
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from granboltz.reproduction.dsmc import read_steady  # noqa: E402
from granboltz.output.files import write_csv  # noqa: E402
from granboltz.reproduction.steady import STEADY_COLUMNS, steady_rows  # noqa: E402

steadies = [read_steady(path) for path in snakemake.input.runs]
(path,) = set(snakemake.input.nosplit)
nosplit = read_steady(path)
rows = steady_rows(steadies, nosplit, snakemake.params.dt_unit)
if snakemake.params.layout == "methods":
    order = {"euler": 0, "strang": 1, "nosplit": 2}
    rows.sort(key=lambda r: order[r["method"]])
write_csv(rows, STEADY_COLUMNS[snakemake.params.layout], snakemake.output.csv, digits=6)
for row in rows:
    print(row, file=sys.stderr)
