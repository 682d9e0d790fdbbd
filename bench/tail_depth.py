#!/usr/bin/python3
"""Tail depth per CPU time: constant weights against SWPM with importance splitting (how deep
each reaches per CPU second; `make bench`).

For GRW05 Examples 7-9 in their steady state (run to 2 t_end, histogram averaged in each ensemble
over 20 times in (t_end, 2 t_end], as the workflow's SWPM runs), runs the simulator once with
constant weights and once per SWPM setting, and reports the CPU seconds (user + system of the
simulator) and the depth reached: the smallest f(r)/f(0) of a shell whose relative confidence
half-width is below 30 % (granboltz.analysis.tail_swpm.resolved_depth), with decades of depth per CPU minute.
The SWPM runs split along the diffusion path (dsmc.weights.split) with the theory tail as
importance function and the workflow's r_s (config/physics.yaml grw05.tails.swpm).

    bench/tail_depth.py [--granboltz build/granboltz] [--examples 7 8 9] [--csv out.csv]
                        [--constant n:N ...] [--swpm kappa:max_particles:n:N ...] [--no-split]
"""
import argparse
import math
import os
import pathlib
import resource
import subprocess
import sys
import tempfile

import yaml

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src" / "python"))

from granboltz.analysis.local_exponent import shells_from_h5  # noqa: E402
from granboltz.analysis.tail_swpm import resolved_depth  # noqa: E402
from granboltz.theory.tail_theory import importance_split  # noqa: E402

# GRW05 §5.3: lambda, t_end (the paper's), histogram radius R (128 shells) and split radius r_s of
# config/physics.yaml grw05.tails.swpm
EXAMPLES = {7: (0.0, 2.5, 130.0, 16.0), 8: (1.0, 0.25, 34.0, 7.5), 9: (0.5, 0.5, 60.0, 10.0)}
BETA, GAMMA, C = 30.0, 16.0, 0.07957747154594767
ROWS = 20


def split_of(example):
    """dsmc.weights.split as the workflow sets it (workflow/rules/grw05_swpm.smk)."""
    lam, _, radius, r_s = EXAMPLES[example]
    return importance_split(lam, BETA, GAMMA, C, radius, r_s, d=3)


def run_config(example, n, N, seed, weights=None):
    lam, t_end, radius, _ = EXAMPLES[example]
    d = {"particles": n, "scheme": "nosplit", "alpha": 0.1, "beta": BETA, "gamma": GAMMA,
         "kernel": {"lambda": lam, "C": C}, "initial": {"temperature": 1.0},
         "t_end": 2 * t_end, "observe_every": t_end / ROWS, "steady_from": t_end, "majorant_update": "paper",
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
        depth, r = resolved_depth(shells_from_h5(out, steady=True))
    return cpu, depth, r


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--granboltz", default=str(ROOT / "build" / "granboltz"))
    p.add_argument("--examples", type=int, nargs="+", default=[7, 8, 9])
    p.add_argument("--constant", nargs="*", default=["100000:16"], help="n:N of constant-weight runs")
    p.add_argument("--swpm", nargs="*", default=["0.25:2000:1000:16"], help="kappa:max_particles:n:N")
    p.add_argument("--reduction", default="energy")
    p.add_argument("--no-split", action="store_true", help="SWPM without importance splitting")
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
            if not a.no_split:
                w["split"] = split_of(ex)
            what = f"kappa={kappa} N_max={nmax} n={n}" + ("" if a.no_split else " split")
            runs.append(("swpm", what, run_config(ex, int(n), int(N), a.seed, w)))
        for method, what, config in runs:
            cpu, depth, r = measure(a.granboltz, config)
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
