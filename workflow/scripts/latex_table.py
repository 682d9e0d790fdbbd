"""LaTeX version of a reproduced table (every table of GRW05, RW05 and TV06 the workflow makes,
e.g. GRW05 Table 1 from results/tables/grw05_table1.csv).

A booktabs tabular (\\toprule, \\midrule, \\bottomrule; needs \\usepackage{booktabs}) with the
CSV's header and cells, special characters escaped and the papers' symbols in the header
(granboltz.report.latex.latex_file). No LaTeX is needed to write it.
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from granboltz.output.files import write_text  # noqa: E402
from granboltz.report.latex import latex_file  # noqa: E402

text = latex_file(snakemake.input.csv)
write_text(text, snakemake.output.tex)
print(text, file=sys.stderr)
