#!/usr/bin/python3
"""Coverage of the Green–Kubo intervals of eta* and D* over independent replicas (`make
check-coverage`; minutes, so not in `make test`).

R replicas (different seeds) of one thermostatted-HCS run with dsmc.correlations, each giving
eta and D with an interval (granboltz.measured.green_kubo_coefficient). The interval is honest
when the replicas' spread equals the sigma it reports (ci/lambda_p): the ratio must lie within
[0.75, 1.33] for R >= 30 (the ratio of a sample sd over 30 replicas to the true sd lies within
that band with probability ~0.995). For lambda = 0 the exact value is known too: the fraction of
replicas whose interval covers it is printed and must be >= 90 % (lambda_p = 3.2 covers 99.86 %
of a normal; the integral's truncation adds a small bias). Exit 1 with the failing line.

    transport_intervals.py [--replicas R] [--binary build/granboltz] [--keep DIR]
"""
import argparse
import math
import pathlib
import statistics
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "src" / "python"))

from granboltz.analysis import transport as measured  # noqa: E402
from granboltz.theory import LAMBDA_P, transport  # noqa: E402
from granboltz.reproduction.transport_table import scales  # noqa: E402

CASES = [  # (label, lambda, alpha, d): the exact check and the hard spheres of the table
    ("maxwell", 0, 0.7, 3),
    ("hard_spheres", 1, 0.5, 3),
]


def config(lam, alpha, d, seed):
    C = 1 / (4 * math.pi) if d == 3 else 1 / (2 * math.pi)
    geometry = "geometry: uniform\n  " if lam == 0 else "majorant: pairwise\n  "
    return f"""model: dsmc
seed: {seed}
ensembles: 32
dsmc:
  particles: 500
  dimension: {d}
  {geometry}alpha: {alpha}
  thermostat: gaussian
  kernel: {{lambda: {lam}, C: {C!r}}}
  t_end: 200
  observe_every: 50
  correlations: {{velocity: {{from: 10, levels: 6}}, stress: {{from: 10, levels: 6}}}}
"""


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--replicas", type=int, default=30)
    ap.add_argument("--binary", default=str(ROOT / "build" / "granboltz"))
    ap.add_argument("--keep", help="keep the replicas' outputs in this folder")
    args = ap.parse_args()
    if args.replicas < 30:
        sys.exit("transport_intervals: --replicas must be >= 30 for the [0.75, 1.33] band")
    folder = pathlib.Path(args.keep or tempfile.mkdtemp(prefix="gk_coverage_"))
    folder.mkdir(parents=True, exist_ok=True)
    failed = []
    for label, lam, alpha, d in CASES:
        s = scales("maxwell" if lam == 0 else "hard_spheres", d, alpha, 1.0, 1.0,
                   1 / (4 * math.pi) if d == 3 else 1 / (2 * math.pi), "uniform" if lam == 0 else None)
        values = {"eta": [], "D": []}
        for k in range(args.replicas):
            cfg = folder / f"{label}_{k}.yaml"
            cfg.write_text(config(lam, alpha, d, 1000 + k))
            out = cfg.with_suffix(".h5")
            subprocess.run([args.binary, "run", str(cfg), "-q", "-o", str(out)], check=True)
            for c in values:
                values[c].append(measured.green_kubo_coefficient(out, c, T=1.0, zeta=s["zeta"], q=s["q"], d=d))
        for c, pairs in values.items():
            v = [x for x, _ in pairs]
            sigma = statistics.fmean(ci for _, ci in pairs) / LAMBDA_P
            ratio = statistics.stdev(v) / sigma
            line = (f"{label} alpha = {alpha} d = {d} {c}: mean {statistics.fmean(v):.4f}, spread {statistics.stdev(v):.4f}, "
                    f"reported sigma {sigma:.4f}, spread/sigma {ratio:.2f}")
            ok = 0.75 <= ratio <= 1.33
            if lam == 0:
                exact = transport.maxwell_coefficients(alpha, d=d)[c]
                covered = sum(abs(x - exact) <= ci for x, ci in pairs) / len(pairs)
                line += f", exact {exact:.4f} covered by {100 * covered:.0f} %"
                ok = ok and covered >= 0.9
            print(("ok   " if ok else "FAIL ") + line, flush=True)
            if not ok:
                failed.append(line)
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
