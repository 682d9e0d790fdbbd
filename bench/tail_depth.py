#!/usr/bin/python3
"""Tail depth per CPU time: constant weights against SWPM (issue 11, item 4; `make bench`).

For GRW05 Examples 7-9 (final state of the steady runs), runs the simulator once with constant
weights and once per SWPM setting, and reports the CPU seconds (user + system of the simulator)
and the depth reached: the smallest f(r)/f(0) of a shell whose relative confidence half-width is
below 30 % (granboltz.tail_swpm.resolved_depth), with log10(depth) per CPU minute.

    bench/tail_depth.py [--granboltz build/granboltz] [--examples 7 8 9] [--csv out.csv]
                        [--constant n:N ...] [--swpm kappa:max_particles:n:N ...]

Defaults: settings of about equal cost per example (2-3 CPU seconds each; measured on 2026-11-30:
constant weights n = 1e5, N = 16 reach 4e-5 (Ex. 7), 6e-5 (8), 4e-5 (9) in 1.5-1.9 s; SWPM kappa =
0.25, N_max = 2000, n = 1000, N = 16 reach 6e-2, 5e-2, 5e-2 in 3.1, 2.5, 1.8 s).
"""
import argparse
import os
import pathlib
import resource
import subprocess
import sys
import tempfile

import yaml

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src" / "python"))

from granboltz.local_exponent import shells_from_h5  # noqa: E402
from granboltz.tail_swpm import resolved_depth  # noqa: E402

# GRW05 §5.3: lambda, t_end (steady state), histogram radius R (128 shells, as the constant-weight runs)
EXAMPLES = {7: (0.0, 2.5, 40.0), 8: (1.0, 0.25, 16.0), 9: (0.5, 0.5, 24.0)}


def run_config(example, n, N, seed, weights=None):
    lam, t_end, radius = EXAMPLES[example]
    d = {"particles": n, "scheme": "nosplit", "alpha": 0.1, "beta": 30.0, "gamma": 16.0,
         "kernel": {"lambda": lam, "C": 0.07957747154594767}, "initial": {"temperature": 1.0},
         "t_end": t_end, "observe_every": t_end, "majorant_update": "paper",
         "histogram": {"shells": 128, "radius": radius}}
    if weights:
        d["weights"] = weights
    return {"model": "dsmc", "seed": seed, "ensembles": N, "dsmc": d}


def measure(granboltz, config, threads=1):
    """(cpu seconds, depth, r) of one run."""
    with tempfile.TemporaryDirectory() as tmp:
        cfg, out = os.path.join(tmp, "run.yaml"), os.path.join(tmp, "run.h5")
        with open(cfg, "w") as f:
            yaml.safe_dump(config, f)
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        subprocess.run([granboltz, "run", cfg, "-o", out, "--threads", str(threads)], check=True,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
        depth, r = resolved_depth(shells_from_h5(out))
    return cpu, depth, r


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--granboltz", default=str(ROOT / "build" / "granboltz"))
    p.add_argument("--examples", type=int, nargs="+", default=[7, 8, 9])
    p.add_argument("--constant", nargs="*", default=["100000:16"], help="n:N of constant-weight runs")
    p.add_argument("--swpm", nargs="*", default=["0.25:2000:1000:16"], help="kappa:max_particles:n:N")
    p.add_argument("--reduction", default="energy")
    p.add_argument("--seed", type=int, default=20260101)
    p.add_argument("--csv")
    a = p.parse_args()
    rows = []
    for ex in a.examples:
        runs = [("constant", f"n={s}", run_config(ex, int(s.split(':')[0]), int(s.split(':')[1]), a.seed))
                for s in a.constant]
        for s in a.swpm:
            kappa, nmax, n, N = s.split(":")
            w = {"method": "swpm", "kappa": float(kappa), "max_particles": int(nmax), "reduction": a.reduction}
            runs.append(("swpm", f"kappa={kappa} N_max={nmax} n={n}", run_config(ex, int(n), int(N), a.seed, w)))
        for method, what, config in runs:
            cpu, depth, r = measure(a.granboltz, config)
            import math
            per_min = -math.log10(depth) / (cpu / 60) if depth == depth and depth > 0 else float("nan")
            rows.append({"example": ex, "method": method, "setting": what, "N": config["ensembles"],
                         "cpu_s": round(cpu, 2), "depth": f"{depth:.2e}", "r_depth": round(r, 2),
                         "decades_per_cpu_min": round(per_min, 2)})
            print("\t".join(str(v) for v in rows[-1].values()), flush=True)
    if a.csv:
        import csv
        with open(a.csv, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)


if __name__ == "__main__":
    main()
