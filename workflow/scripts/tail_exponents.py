"""GRW05 §5.3 (Examples 7, 8, 9; Figs. 5-7): the tail exponents b of eq. (38).

For each example, the least-squares slope b (with its standard error, scipy linregress) of
y_k = ln(ln f_k0 - ln f_k) against x_k = ln(k - k0), shell index k, on params.tails.fit_window,
from the final histogram (params.tails.histogram: the shell fractions of eq. 37 divided by the
shell volumes, "density", or as they are, "fraction"); theory b = 1 + lambda/2 (eqs. 20, 21).
Output csv: the exponent table (granboltz_common.TAIL_COLUMNS); output windows: b of every
example on every window of params.tails.windows and for both normalisations (WINDOW_COLUMNS).
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import granboltz_common as gc  # noqa: E402

tails = snakemake.params.tails
hists = {}
for name in ("ex7", "ex8", "ex9"):
    (path,) = getattr(snakemake.input, name)
    hists[int(name[2:])] = gc.read_histogram(path)
rows, wrows = gc.tail_rows(hists, tails)
gc.write_csv(rows, gc.TAIL_COLUMNS, snakemake.output.csv, digits=6)
gc.write_csv(wrows, gc.WINDOW_COLUMNS, snakemake.output.windows, digits=6)
for row in rows + wrows:
    print(row, file=sys.stderr)
