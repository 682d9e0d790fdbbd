"""TV06 §4: the DSMC version of the 1-D intruder against the Gillespie algorithm, Gaussian bath.

One row per (M, alpha): T/T_B of both methods with their 99.9 % confidence intervals over the N
ensembles, the exact value of eq. (18), the difference DSMC - Gillespie against the joint
interval hypot(ci_G, ci_D) (independent runs), and the cost: core nanoseconds per collision of
each method (the simulator's wall time x threads / collisions, warm-up included) and the DSMC
candidates per collision (granboltz.reproduction.tv06_tables.dsmc_rows).
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

from granboltz.output.files import write_csv  # noqa: E402
from granboltz.reproduction.tv06_tables import DSMC_COLUMNS, dsmc_rows, read_tv06  # noqa: E402

gillespie = [read_tv06(path) for path in snakemake.input.gillespie]
dsmc = [read_tv06(path) for path in snakemake.input.dsmc]
for runs, method in ((gillespie, "gillespie"), (dsmc, "dsmc")):
    bad = [r["path"] for r in runs if r["model"] != "intruder" or r["method"] != method or r["bath"] != "gaussian"]
    if bad:
        raise ValueError(f"§4 needs Gaussian-bath intruder runs with method {method}: {bad}")
rows = dsmc_rows(gillespie, dsmc)
write_csv(rows, DSMC_COLUMNS, snakemake.output.csv, digits=6)
for r in rows:
    print(f"M = {r['M']:g}, alpha = {r['alpha']:g}: Gillespie {r['T_gillespie']:.5f} ± {r['ci_gillespie']:.5f}, "
          f"DSMC {r['T_dsmc']:.5f} ± {r['ci_dsmc']:.5f}, exact {r['exact']:.5f}, agree: {r['agree']}", file=sys.stderr)
