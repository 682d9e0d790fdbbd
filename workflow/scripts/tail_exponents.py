"""GRW05 §5.3 (Examples 7, 8, 9; Figs. 5-7): the tail exponents b of eq. (38).

For each example, the least-squares slope b (with its standard error, scipy linregress) of
y_k = ln(ln f_k0 - ln f_k) against x_k = ln(k - k0), shell index k, on params.tails.fit_window,
from the final histogram (params.tails.histogram: the shell fractions of eq. 37 divided by the
shell volumes, "density", or as they are, "fraction"); theory b = 1 + lambda/2 (eqs. 20, 21).
Output csv: the exponent table (granboltz.analysis.tails.TAIL_COLUMNS); output windows: b of every
example on every window of params.tails.windows and for both normalisations (WINDOW_COLUMNS).
The exponent table also takes the local-exponent numbers of each example (input local: the
summaries of rule grw05_tail_local_ex*, granboltz.analysis.tail_local; columns tails.LOCAL_COLUMNS) and the
weighted-particle numbers (input swpm: the summaries of rule grw05_tail_swpm_ex*,
granboltz.analysis.tail_swpm; columns tails.SWPM_COLUMNS).
"""

import json
import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from granboltz.reproduction.dsmc import read_histogram  # noqa: E402
from granboltz.output.files import write_csv  # noqa: E402
from granboltz.analysis.tails import LOCAL_COLUMNS, SWPM_COLUMNS, TAIL_COLUMNS, tail_rows, WINDOW_COLUMNS  # noqa: E402

tails = snakemake.params.tails
hists = {}
for name in ("ex7", "ex8", "ex9"):
    (path,) = getattr(snakemake.input, name)
    hists[int(name[2:])] = read_histogram(path)
local = {}
for path in snakemake.input.local:
    with open(path) as f:
        numbers = json.load(f)["numbers"]
    local[int(numbers["example"])] = numbers
swpm = {}
for path in snakemake.input.swpm:
    with open(path) as f:
        numbers = json.load(f)["numbers"]
    swpm[int(numbers["example"])] = numbers
rows, wrows = tail_rows(hists, tails, local, swpm)
write_csv(rows, TAIL_COLUMNS + LOCAL_COLUMNS + SWPM_COLUMNS, snakemake.output.csv, digits=6)
write_csv(wrows, WINDOW_COLUMNS, snakemake.output.windows, digits=6)
for row in rows + wrows:
    print(row, file=sys.stderr)
