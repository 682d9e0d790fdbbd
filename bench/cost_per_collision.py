#!/usr/bin/python3
"""CPU time per real collision of the new set-ups against the d = 3 constant-alpha run of the
same config: disks (dsmc.dimension: 2) and the viscoelastic law, interleaved, medians.

    bench/cost_per_collision.py [BINARY] [--repeat 5]

Prints one line per config: ns per real collision and the ratio to d = 3 with constant alpha.
The table of docs/performance.md ("Disks and viscoelastic restitution") came from it.
"""
import argparse
import os
import statistics
import subprocess
import tempfile

import h5py
import yaml

BASE = {"model": "dsmc", "seed": 5, "ensembles": 1,
        "dsmc": {"particles": 20000, "kernel": {"lambda": 1, "C": 0.07957747154594767}, "observe_every": 2}}
CASES = {  # name: dsmc keys over BASE
    "hard spheres, white noise, global": {"beta": 1.0, "t_end": 60},
    "Maxwell, Gaussian": {"thermostat": "gaussian", "kernel": {"lambda": 0, "C": 0.07957747154594767}, "t_end": 2000},
    "hard spheres, Gaussian, pairwise": {"thermostat": "gaussian", "majorant": "pairwise", "t_end": 600},
}
PLANE = {"dimension": 2}  # with C = 1/(2 pi): the same collision frequency as 1/(4 pi) in d = 3
VISCO = {"restitution": {"law": "viscoelastic", "delta": 0.3}}
VARIANTS = {"d = 3, alpha": {"alpha": 0.5}, "d = 2, alpha": {"alpha": 0.5, **PLANE},
            "d = 3 viscoelastic": VISCO, "d = 2 viscoelastic": {**VISCO, **PLANE}}


def config(case, variant):
    d = {**BASE["dsmc"], **CASES[case], **VARIANTS[variant]}
    if variant.startswith("d = 2"):
        d["kernel"] = {**d["kernel"], "C": 2 * d["kernel"]["C"]}
    return {**BASE, "dsmc": d}


def ns_per_collision(binary, cfg, tmp):
    path, out = os.path.join(tmp, "c.yaml"), os.path.join(tmp, "c.h5")
    with open(path, "w") as f:
        yaml.safe_dump(cfg, f)
    if os.path.exists(out):
        os.remove(out)
    proc = subprocess.Popen([binary, "run", path, "-q", "--threads", "1", "-o", out])
    _, status, usage = os.wait4(proc.pid, 0)
    if status != 0:
        raise SystemExit(f"{binary} failed on {cfg}")
    with h5py.File(out) as h:
        collisions = h["events/collisions"][:].sum()
    return (usage.ru_utime + usage.ru_stime) / collisions * 1e9


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("binary", nargs="?", default="build/granboltz")
    ap.add_argument("--repeat", type=int, default=5)
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        for case in CASES:
            times = {v: [] for v in VARIANTS}
            for _ in range(a.repeat):
                for v in VARIANTS:
                    times[v].append(ns_per_collision(a.binary, config(case, v), tmp))
            base = statistics.median(times["d = 3, alpha"])
            print(f"{case}: " + " | ".join(
                f"{v} {statistics.median(t):.0f} ns ({statistics.median(t) / base:.2f}x)" for v, t in times.items()))


if __name__ == "__main__":
    main()
