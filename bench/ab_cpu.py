#!/usr/bin/python3
"""Interleaved A/B of two granboltz binaries on one config: CPU time (user + sys) of each run,
old and new alternating, so that both see the same minutes of a shared, noisy machine.

    bench/ab_cpu.py OLD NEW CONFIG [--repeat 9] [--set key=value ...]

Prints the median CPU time of each, the median of the paired ratios new/old and its 95 %
bootstrap interval (10^4 resamples of the pairs, fixed seed). The gate for a refactor: it fails if
the interval's lower end exceeds 1.03; an interval that straddles 1.03 needs more repetitions.
"""
import argparse
import os
import random
import statistics
import subprocess
import tempfile


def cpu_seconds(exe, config, sets, output):
    args = [exe, "run", config, "-q", "--threads", "1", "-o", output]
    for s in sets:
        args += ["--set", s]
    proc = subprocess.Popen(args)
    _, status, usage = os.wait4(proc.pid, 0)
    if status != 0:
        raise SystemExit(f"{exe} failed on {config} (status {status})")
    return usage.ru_utime + usage.ru_stime


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("config")
    ap.add_argument("--repeat", type=int, default=9)
    ap.add_argument("--set", action="append", default=[], dest="sets")
    a = ap.parse_args()
    times = {"old": [], "new": []}
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "out.h5")
        for _ in range(a.repeat):
            for label in ("old", "new"):
                times[label].append(cpu_seconds(getattr(a, label), a.config, a.sets, out))
    old, new = statistics.median(times["old"]), statistics.median(times["new"])
    ratios = [n / o for o, n in zip(times["old"], times["new"])]
    paired = statistics.median(ratios)
    rng = random.Random(1)
    boot = sorted(statistics.median(rng.choices(ratios, k=len(ratios))) for _ in range(10000))
    lo, hi = boot[249], boot[9749]
    verdict = "slower (fails)" if lo > 1.03 else "undecided: repeat more" if hi > 1.03 else "within 3 %"
    print(f"CPU old {old:.3f} s, new {new:.3f} s (medians of {a.repeat}); paired new/old {paired:.3f} "
          f"[{lo:.3f}, {hi:.3f}] 95 % bootstrap: {verdict}")


if __name__ == "__main__":
    main()
