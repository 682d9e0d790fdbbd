#!/usr/bin/python3
"""The peer problem run by SPARTA: elastic hard spheres (argon, VSS omega = 1/2, alpha = 1, the
data/ar.hs file of SPARTA) in one periodic cell, NTC collisions, serial. Prints and writes SPARTA's
loop time per real collision (median of --repeat runs) for n = 10^4, 10^5, 10^6, as lines
"n,ns_per_real_collision" for granboltz_bench --sparta.

Usage (make bench-peer): sparta_peer.py /path/to/spa_serial [--repeat R] [--out FILE]. The SPARTA
build must be the user's own (SPARTA is GPL; nothing of it is copied here): the species and
collision files are looked up next to the binary as ../data/ar.species (or ../bench/ar.species)
and ../data/ar.hs.
"""
import argparse
import math
import os
import re
import statistics
import subprocess
import sys
import tempfile

DECK = """seed 12345
dimension 3
boundary p p p
create_box 0 {L} 0 {L} 0 {L}
create_grid 1 1 1
species {species} Ar
mixture gas Ar vstream 0.0 0.0 0.0 temp 273.15
global nrho 7.07043E22
global fnum {fnum}
collide vss gas {vss}
create_particles gas n {n}
stats {steps}
stats_style step cpu np ncollave nattemptave
timestep 7.0E-8
run {steps}
"""


def find(binary, names):
    root = os.path.dirname(os.path.dirname(os.path.abspath(binary)))
    for name in names:
        path = os.path.join(root, name)
        if os.path.exists(path):
            return path
    sys.exit(f"sparta_peer.py: none of {names} found under {root}")


def run_once(binary, n, species, vss):
    L = 1.0e-4
    # About 0.56 collisions per particle per step at this density and time step (the homogeneous
    # problem has no other time scale; at 10x smaller steps the particle moves dominate SPARTA's
    # loop time): 2*10^6 collisions in all.
    steps = max(20, math.ceil(2.0e6 / (0.28 * n)))
    deck = DECK.format(L=L, fnum=7.07043e22 * L**3 / n, n=n, steps=steps, species=species,
                       vss=vss)
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "in.peer")
        with open(path, "w") as f:
            f.write(deck)
        out = subprocess.run([binary, "-in", path, "-log", os.path.join(tmp, "log")], cwd=tmp,
                             capture_output=True, text=True, check=True).stdout
    loop = re.search(r"Loop time of ([0-9.eE+-]+) on 1 procs for (\d+) steps", out)
    if not loop:
        sys.exit("sparta_peer.py: no 'Loop time' line in SPARTA's output:\n" + out[-2000:])
    rows = [line.split() for line in out.splitlines()
            if re.match(r"\s*\d+\s+[0-9.eE+-]+\s+\d+\s+[0-9.eE+-]+\s+[0-9.eE+-]+\s*$", line)]
    ncollave = float(rows[-1][3])
    collisions = ncollave * int(loop.group(2))
    return 1e9 * float(loop.group(1)) / collisions


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("binary")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--out", default="bench/sparta.csv")
    a = ap.parse_args()
    species = find(a.binary, ["data/ar.species", "bench/ar.species"])
    vss = find(a.binary, ["data/ar.hs"])
    lines = []
    for n in (10**4, 10**5, 10**6):
        ns = statistics.median(run_once(a.binary, n, species, vss) for _ in range(a.repeat))
        print(f"SPARTA n = {n:.0e}: {ns:.1f} ns per real collision (median of {a.repeat})")
        lines.append(f"{n},{ns:.2f}\n")
    with open(a.out, "w") as f:
        f.writelines(lines)


if __name__ == "__main__":
    main()
