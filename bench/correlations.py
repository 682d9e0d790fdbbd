#!/usr/bin/python3
"""The cost of time correlations: bench/correlations.yaml run without and with
dsmc.correlations (each of velocity, stress, heat_flux at its defaults, then all three),
interleaved, CPU time per run (user + sys of the child), medians over --repeat runs.
Usage: bench/correlations.py [BINARY] [--repeat 7]"""
import argparse
import os
import pathlib
import statistics
import subprocess
import tempfile

HERE = pathlib.Path(__file__).resolve().parent
CASES = {"none": None, "velocity": "{velocity: {}}", "stress": "{stress: {}}",
         "heat_flux": "{heat_flux: {}}", "all": "{velocity: {}, stress: {}, heat_flux: {}}"}


def cpu(binary, config, out):
    before = os.times()
    subprocess.run([binary, "run", str(config), "-q", "--threads", "1", "-o", out], check=True)
    after = os.times()
    return (after.children_user - before.children_user) + (after.children_system - before.children_system)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("binary", nargs="?", default=str(HERE.parent / "build" / "granboltz"))
    p.add_argument("--repeat", type=int, default=7)
    a = p.parse_args()
    base = (HERE / "correlations.yaml").read_text()
    times = {k: [] for k in CASES}
    with tempfile.TemporaryDirectory() as tmp:
        configs = {}
        for k, v in CASES.items():
            configs[k] = pathlib.Path(tmp) / f"{k}.yaml"
            configs[k].write_text(base + (f"  correlations: {v}\n" if v else ""))
        for _ in range(a.repeat):
            for k in CASES:
                out = str(pathlib.Path(tmp) / f"{k}.h5")
                times[k].append(cpu(a.binary, configs[k], out))
                os.unlink(out)
    ref = statistics.median(times["none"])
    for k, t in times.items():
        m = statistics.median(t)
        print(f"{k:10s} median {m:7.3f} s   {100 * (m / ref - 1):+6.1f} %")


if __name__ == "__main__":
    main()
