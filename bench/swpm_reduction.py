#!/usr/bin/python3
"""Weighted particles (SWPM) against constant weights: the steady a2 of hard spheres.

For each thermostat (white noise with beta = 1/2, Gaussian), alpha and SWPM setting (reduction,
with or without split), runs the simulator once with constant weights and once with SWPM
(kappa = 1/4, N_max = 3n, independent seeds) and prints both steady a2 with their 95 % half-widths
and z, the difference over the half-width of the difference. A reduction that keeps every moment
in expectation gives |z| of order 1; the energy merges gave z = -17 ... -34 (docs/config.md,
"Reduction"). The configurations the simulator refuses are reported as such.

    bench/swpm_reduction.py [--granboltz build/granboltz] [--particles 120] [--ensembles 40]
                            [--t-end 40] [--alphas 0.6 0.8] [--reductions unbiased energy]
                            [--split both|on|off]
"""
import argparse
import itertools
import math
import pathlib
import subprocess
import sys
import tempfile

import h5py
import yaml

ROOT = pathlib.Path(__file__).resolve().parents[1]
KERNEL = {"lambda": 1, "C": 0.07957747154594767}  # hard spheres, 1/(4 pi)
# An importance function near the steady tail (any is unbiased; a close one lowers the variance).
SPLIT = {"radius": 4.0, "rate": 1.5, "power": 1.0, "interval": 0.05}


def steady_a2(binary, workdir, name, config):
    path = pathlib.Path(workdir) / f"{name}.yaml"
    out = path.with_suffix(".h5")
    path.write_text(yaml.safe_dump(config, sort_keys=False))
    r = subprocess.run([binary, "run", str(path), "-o", str(out), "-q"], capture_output=True,
                       text=True)
    if r.returncode != 0:
        return None, r.stderr.strip().splitlines()[-1] if r.stderr.strip() else f"exit {r.returncode}"
    with h5py.File(out, "r") as f:
        value = (float(f["steady/a2/mean"][()]), float(f["steady/a2/ci"][()]))
    out.unlink()
    return value, ""


def config(args, thermostat, alpha, seed, weights=None):
    d = {"particles": args.particles, "alpha": alpha, "kernel": KERNEL, "t_end": args.t_end,
         "observe_every": 0.5, "steady_from": 10.0, "moments": 2}
    d.update({"thermostat": "gaussian", "beta": 0} if thermostat == "gaussian" else {"beta": 0.5})
    if weights:
        d["weights"] = weights
    return {"model": "dsmc", "seed": seed, "ensembles": args.ensembles, "dsmc": d}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--granboltz", default=str(ROOT / "build" / "granboltz"))
    ap.add_argument("--particles", type=int, default=120)
    ap.add_argument("--ensembles", type=int, default=40)
    ap.add_argument("--t-end", type=float, default=40.0)
    ap.add_argument("--alphas", type=float, nargs="+", default=[0.6, 0.8])
    ap.add_argument("--reductions", nargs="+", default=["unbiased", "energy"])
    ap.add_argument("--split", choices=["both", "on", "off"], default="both")
    args = ap.parse_args()
    splits = {"both": [False, True], "on": [True], "off": [False]}[args.split]
    print(f"n = {args.particles}, N = {args.ensembles}, t_end = {args.t_end}, steady from t = 10, "
          f"kappa = 1/4, N_max = 3n")
    print(f"{'thermostat':12s} {'alpha':>5s} {'reduction':9s} {'split':5s} "
          f"{'constant a2':>18s} {'swpm a2':>18s} {'z':>7s}")
    with tempfile.TemporaryDirectory(prefix="swpm-reduction-") as tmp:
        for thermostat, alpha in itertools.product(["white_noise", "gaussian"], args.alphas):
            c, err = steady_a2(args.granboltz, tmp, "constant", config(args, thermostat, alpha, 11))
            if c is None:
                sys.exit(f"constant weights failed: {err}")
            for reduction, split in itertools.product(args.reductions, splits):
                w = {"method": "swpm", "kappa": 0.25, "max_particles": 3 * args.particles,
                     "reduction": reduction}
                if split:
                    w["split"] = SPLIT
                s, err = steady_a2(args.granboltz, tmp, "swpm",
                                   config(args, thermostat, alpha, 12, w))
                head = f"{thermostat:12s} {alpha:5.2f} {reduction:9s} {str(split):5s} " \
                       f"{c[0]:+9.4f} ± {c[1]:.4f}"
                if s is None:
                    print(f"{head}  refused or failed: {err}", flush=True)
                    continue
                z = (s[0] - c[0]) / math.hypot(c[1], s[1])
                print(f"{head} {s[0]:+9.4f} ± {s[1]:.4f} {z:+7.2f}", flush=True)


if __name__ == "__main__":
    main()
