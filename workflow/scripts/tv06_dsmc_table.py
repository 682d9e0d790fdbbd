"""TV06 §4: the DSMC version of the 1-D intruder against the Gillespie algorithm, Gaussian bath.

One row per (M, alpha): T/T_B of both methods with their 99.9 % confidence intervals over the N
ensembles, the exact value of eq. (18), the difference DSMC - Gillespie against the joint
interval hypot(ci_G, ci_D) (independent runs), and the cost: core nanoseconds per collision of
each method (the simulator's wall time x threads / collisions, warm-up included) and the DSMC
candidates per collision (tv06_common.dsmc_rows).
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import granboltz_common as gc  # noqa: E402
import tv06_common as tv  # noqa: E402

gillespie = [tv.read_tv06(path) for path in snakemake.input.gillespie]
dsmc = [tv.read_tv06(path) for path in snakemake.input.dsmc]
for runs, method in ((gillespie, "gillespie"), (dsmc, "dsmc")):
    bad = [r["path"] for r in runs if r["model"] != "intruder" or r["method"] != method or r["bath"] != "gaussian"]
    if bad:
        raise ValueError(f"§4 needs Gaussian-bath intruder runs with method {method}: {bad}")
rows = tv.dsmc_rows(gillespie, dsmc)
gc.write_csv(rows, tv.DSMC_COLUMNS, snakemake.output.csv, digits=6)
for r in rows:
    print(f"M = {r['M']:g}, alpha = {r['alpha']:g}: Gillespie {r['T_gillespie']:.5f} ± {r['ci_gillespie']:.5f}, "
          f"DSMC {r['T_dsmc']:.5f} ± {r['ci_dsmc']:.5f}, exact {r['exact']:.5f}, agree: {r['agree']}", file=sys.stderr)
